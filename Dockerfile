# Production image: gunicorn serving Django, or a Celery worker/beat from the same image.
FROM python:3.11-slim
ENV PYTHONDONTWRITEBYTECODE=1 PYTHONUNBUFFERED=1 CONTINUUM_VAR_DIR=/var/lib/continuum
WORKDIR /app
COPY requirements.txt .
RUN pip install --no-cache-dir -r requirements.txt
COPY . .
# Everything runs as an unprivileged user that owns only its state directory (not the code): a compromised
# process can neither rewrite the application nor act as root in the container.
RUN useradd --system --uid 10001 --create-home --home-dir /home/continuum continuum \
    && mkdir -p /var/lib/continuum && chown continuum:continuum /var/lib/continuum && chmod 700 /var/lib/continuum
USER continuum
# Static files at build time, with a throw-away secret key: none is baked into the image (compose and the
# manifests give SECRET_KEY and CONTINUUM_CREDENTIALS_KEY at run time).
RUN SECRET_KEY=collectstatic-only python manage.py collectstatic --no-input -v0 \
    && rm -rf /home/continuum/.config/continuum
EXPOSE 8000
CMD ["gunicorn", "continuum.wsgi:application", "--bind", "0.0.0.0:8000", "--workers", "3"]
