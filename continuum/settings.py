"""Django settings, read from the environment.

DATABASE_URL       default: a SQLite file under var/ (the embedded quick-start default)
CELERY_BROKER_URL  default: none, and then jobs run in-process (eager) so the quick start needs no server
SECRET_KEY, DEBUG, ALLOWED_HOSTS
CONTINUUM_*        algorithm defaults where the thesis is ambiguous (see continuum/engine docstrings)
"""

import os
import shlex
from pathlib import Path

import dj_database_url

BASE_DIR = Path(__file__).resolve().parent.parent
VAR_DIR = Path(os.environ.get("CONTINUUM_VAR_DIR", BASE_DIR / "var"))


def env_bool(name: str, default: bool) -> bool:
    value = os.environ.get(name)
    return default if value is None else value.strip().lower() in {"1", "true", "yes", "on"}


DEBUG = env_bool("DEBUG", False)


def _secret_key() -> str:
    """SECRET_KEY from the environment, else a random key kept in var/secret_key (never a fixed one)."""
    if os.environ.get("SECRET_KEY"):
        return os.environ["SECRET_KEY"]
    path = VAR_DIR / "secret_key"
    if not path.exists():
        import secrets

        VAR_DIR.mkdir(parents=True, exist_ok=True)
        path.write_text(secrets.token_urlsafe(50))
        path.chmod(0o600)
    return path.read_text().strip()


SECRET_KEY = _secret_key()
ALLOWED_HOSTS = os.environ.get("ALLOWED_HOSTS", "localhost,127.0.0.1,[::1],testserver").split(",")
CSRF_TRUSTED_ORIGINS = [o for o in os.environ.get("CSRF_TRUSTED_ORIGINS", "").split(",") if o]

INSTALLED_APPS = [
    "django.contrib.admin",
    "django.contrib.auth",
    "django.contrib.contenttypes",
    "django.contrib.sessions",
    "django.contrib.messages",
    "django.contrib.staticfiles",
    "rest_framework",
    "django_filters",
    "drf_spectacular",
    "drf_spectacular_sidecar",
    "apps.tenancy",
    "apps.clusters",
    "apps.workloads",
    "apps.jobs",
    "apps.scheduling",
    "apps.kube",
    "apps.containers",
    "apps.realtime",
    "apps.heft4k",
    "apps.verification",
    "apps.devices",
    "apps.dashboard",
]

MIDDLEWARE = [
    "django.middleware.security.SecurityMiddleware",
    "whitenoise.middleware.WhiteNoiseMiddleware",
    "django.contrib.sessions.middleware.SessionMiddleware",
    "django.middleware.common.CommonMiddleware",
    "apps.tenancy.bounds.RejectNulMiddleware",
    "django.middleware.csrf.CsrfViewMiddleware",
    "django.contrib.auth.middleware.AuthenticationMiddleware",
    "django.contrib.messages.middleware.MessageMiddleware",
    "django.middleware.clickjacking.XFrameOptionsMiddleware",
]

ROOT_URLCONF = "continuum.urls"
TEMPLATES = [
    {
        "BACKEND": "django.template.backends.django.DjangoTemplates",
        "DIRS": [BASE_DIR / "templates"],
        "APP_DIRS": True,
        "OPTIONS": {
            "context_processors": [
                "django.template.context_processors.request",
                "django.contrib.auth.context_processors.auth",
                "django.contrib.messages.context_processors.messages",
            ]
        },
    }
]
WSGI_APPLICATION = "continuum.wsgi.application"
ASGI_APPLICATION = "continuum.asgi.application"

DATABASES = {
    "default": dj_database_url.parse(
        os.environ.get("DATABASE_URL") or f"sqlite:///{VAR_DIR / 'continuum.sqlite3'}", conn_max_age=60
    )
}
if DATABASES["default"]["ENGINE"].endswith("sqlite3"):
    # A file, not memory, so that a real worker process can share the test database.
    DATABASES["default"]["TEST"] = {"NAME": str(VAR_DIR / "test.sqlite3")}
DEFAULT_AUTO_FIELD = "django.db.models.BigAutoField"

AUTH_PASSWORD_VALIDATORS = [
    {"NAME": "django.contrib.auth.password_validation.MinimumLengthValidator"},
]
LOGIN_URL = "login"
LOGIN_REDIRECT_URL = "dashboard:home"
LOGOUT_REDIRECT_URL = "login"

LANGUAGE_CODE = "en-us"
TIME_ZONE = "UTC"
USE_I18N = True
USE_TZ = True

STATIC_URL = "static/"
STATICFILES_DIRS = [BASE_DIR / "static"]
STATIC_ROOT = VAR_DIR / "staticfiles"
STATIC_ROOT.mkdir(parents=True, exist_ok=True)  # whitenoise warns about a missing root
# Serve static files (plotly.js included) from the app itself; no CDN.
WHITENOISE_USE_FINDERS = True

REST_FRAMEWORK = {
    "DEFAULT_AUTHENTICATION_CLASSES": [
        "apps.tenancy.authentication.FleetTokenAuthentication",
        "rest_framework.authentication.SessionAuthentication",
    ],
    "DEFAULT_PERMISSION_CLASSES": ["rest_framework.permissions.IsAuthenticated"],
    "DEFAULT_FILTER_BACKENDS": [
        "django_filters.rest_framework.DjangoFilterBackend",
        "rest_framework.filters.OrderingFilter",
        "rest_framework.filters.SearchFilter",
    ],
    "DEFAULT_PAGINATION_CLASS": "apps.tenancy.bounds.BoundedLimitOffsetPagination",
    "DEFAULT_PARSER_CLASSES": [
        "apps.tenancy.bounds.SafeJSONParser",
        "apps.tenancy.bounds.SafeFormParser",
        "apps.tenancy.bounds.SafeMultiPartParser",
    ],
    "PAGE_SIZE": 50,
    "DEFAULT_SCHEMA_CLASS": "drf_spectacular.openapi.AutoSchema",
    "EXCEPTION_HANDLER": "apps.tenancy.api.exception_handler",
}
SPECTACULAR_SETTINGS = {
    "TITLE": "Continuum API",
    "DESCRIPTION": "Control plane for ROS-based robot software on the edge-cloud continuum.",
    "VERSION": "1.0.0",
    "SERVE_INCLUDE_SCHEMA": False,
    "SERVE_PERMISSIONS": ["rest_framework.permissions.IsAuthenticated"],
    "COMPONENT_SPLIT_REQUEST": True,
    # Swagger UI and ReDoc served from our static files, never from a CDN.
    "SWAGGER_UI_DIST": "SIDECAR",
    "SWAGGER_UI_FAVICON_HREF": "SIDECAR",
    "REDOC_DIST": "SIDECAR",
    "ENUM_NAME_OVERRIDES": {"AlgorithmEnum": "apps.scheduling.serializers.ALGORITHM_CHOICES"},
}

# ---- Celery ---------------------------------------------------------------------------------------
CELERY_BROKER_URL = os.environ.get("CELERY_BROKER_URL", "")
# With no broker the quick start runs jobs in-process; the job record, progress and errors are the same.
CELERY_TASK_ALWAYS_EAGER = not CELERY_BROKER_URL
CELERY_TASK_EAGER_PROPAGATES = False
CELERY_TASK_DEFAULT_QUEUE = os.environ.get("CELERY_QUEUE", "continuum")
CELERY_TASK_ACKS_LATE = True
CELERY_TASK_REJECT_ON_WORKER_LOST = True
CELERY_WORKER_PREFETCH_MULTIPLIER = 1
CELERY_TASK_SERIALIZER = "json"
CELERY_ACCEPT_CONTENT = ["json"]
CELERY_RESULT_BACKEND = None
# A job whose worker died unacknowledged is redelivered after the visibility timeout (longer than any job).
CELERY_BROKER_TRANSPORT_OPTIONS = {
    "visibility_timeout": int(os.environ.get("CELERY_VISIBILITY_TIMEOUT", 3600)),
    "unacked_restore_interval": int(os.environ.get("CELERY_RESTORE_INTERVAL", 10)),
    "unacked_restore_throttle": int(os.environ.get("CELERY_RESTORE_THROTTLE", 10)),
}
CELERY_BROKER_CONNECTION_RETRY_ON_STARTUP = True
# `celery -A continuum beat`: lifts RT-Kube's expired node taints (the rt_scheduler process does it too).
CELERY_BEAT_SCHEDULE = {"rt-lift-taints": {"task": "continuum.rt_lift_taints", "schedule": 5.0}}

# ---- Continuum ------------------------------------------------------------------------------------
# HEFT's average computation cost: "mean" (literature, Topcuoglu) or "max" (thesis Fig. 3.1). Spec 01 2.1.
CONTINUUM_HEFT_RANK_MODE = os.environ.get("CONTINUUM_HEFT_RANK_MODE", "mean")
# How cluster nodes without a direct link reach each other: "ospf" (least sum of 1/bandwidth, store and
# forward; spec 02 section 6.1) or "latency" (least latency, bottleneck bandwidth).
CONTINUUM_CLUSTER_ROUTING = os.environ.get("CONTINUUM_CLUSTER_ROUTING", "ospf")
# Scheduler name written into pods Continuum places; kube-scheduler leaves them alone.
CONTINUUM_SCHEDULER_NAME = os.environ.get("CONTINUUM_SCHEDULER_NAME", "continuum-scheduler")
CONTINUUM_DEFAULT_NAMESPACE = os.environ.get("CONTINUUM_NAMESPACE", "continuum")
CONTINUUM_POD_IMAGE = os.environ.get("CONTINUUM_POD_IMAGE", "registry.k8s.io/pause:3.9")
# The command a pushed pod's container runs (the image's entrypoint, which a manifest cannot read). It is
# spelled out because HEFT4K wraps it as `nice -n N -- <command>` (README, HEFT4K): the image must then
# contain CONTINUUM_NICE_BINARY.
CONTINUUM_POD_COMMAND = shlex.split(os.environ.get("CONTINUUM_POD_COMMAND", "/pause"))
CONTINUUM_NICE_BINARY = os.environ.get("CONTINUUM_NICE_BINARY", "nice")
# HEFT4K remapping (Algorithm 2): total remap when the lost HEFT-rank share exceeds this fraction.
CONTINUUM_REMAP_THRESHOLD = float(os.environ.get("CONTINUUM_REMAP_THRESHOLD", "0.2"))
# ---- Limits (continuum/engine/limits.py; README "Limits"; CONTINUUM_MAX_<NAME> overrides) -----------
from continuum.engine import limits as _limits  # noqa: E402

CONTINUUM_LIMITS = _limits.get()
# Largest request body (JSON documents) and largest uploaded file (the import endpoints check each file's
# size against the same number, since Django's limit leaves file parts out).
DATA_UPLOAD_MAX_MEMORY_SIZE = CONTINUUM_LIMITS.upload_bytes
# Files above this are spooled to a temporary file instead of memory while they are read.
FILE_UPLOAD_MAX_MEMORY_SIZE = 2_621_440
# Celery: a job past the soft limit fails with "time limit of N s exceeded"; the hard limit kills the
# worker child; a child above the memory limit (KiB, resident) is replaced after its current job.
CELERY_TASK_SOFT_TIME_LIMIT = int(os.environ.get("CONTINUUM_JOB_SOFT_TIME_LIMIT", 600))
CELERY_TASK_TIME_LIMIT = int(os.environ.get("CONTINUUM_JOB_TIME_LIMIT", CELERY_TASK_SOFT_TIME_LIMIT + 60))
CELERY_WORKER_MAX_MEMORY_PER_CHILD = int(os.environ.get("CONTINUUM_WORKER_MAX_MEMORY_KIB", 2 * 1024 * 1024))
# Address-space cap of each prefork worker child (MiB, 0: none): a job past it fails with that reason.
CONTINUUM_JOB_MEMORY_LIMIT_MIB = int(os.environ.get("CONTINUUM_JOB_MEMORY_LIMIT_MIB", 4096))

LOGGING = {
    "version": 1,
    "disable_existing_loggers": False,
    "handlers": {"console": {"class": "logging.StreamHandler"}},
    "root": {"handlers": ["console"], "level": os.environ.get("LOG_LEVEL", "INFO")},
}

# Assertion-based verification: the Redis of the monitor handlers' networks (one key prefix per cluster,
# CONTINUUM_VERIFICATION_PREFIX:<cluster id>). Empty: events posted to the API are evaluated in-process.
CONTINUUM_VERIFICATION_REDIS_URL = os.environ.get("CONTINUUM_VERIFICATION_REDIS_URL", "")
CONTINUUM_VERIFICATION_PREFIX = os.environ.get("CONTINUUM_VERIFICATION_PREFIX", "cv")
# A handler that has not reported for this many seconds is considered gone (3 stats periods, spec 03 §9).
CONTINUUM_HANDLER_LIVENESS_S = float(os.environ.get("CONTINUUM_HANDLER_LIVENESS_S", "3"))
