# Production image: gunicorn serving Django, or a Celery worker/beat from the same image.
FROM python:3.11-slim
ENV PYTHONDONTWRITEBYTECODE=1 PYTHONUNBUFFERED=1 CONTINUUM_VAR_DIR=/var/lib/continuum
WORKDIR /app
COPY requirements.txt .
RUN pip install --no-cache-dir -r requirements.txt
COPY . .
RUN mkdir -p /var/lib/continuum && python manage.py collectstatic --no-input -v0
EXPOSE 8000
CMD ["gunicorn", "continuum.wsgi:application", "--bind", "0.0.0.0:8000", "--workers", "3"]
