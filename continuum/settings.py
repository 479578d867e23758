"""Django settings, read from the environment.

DATABASE_URL       default: a SQLite file under var/ (the embedded quick-start default)
CELERY_BROKER_URL  default: a broker in files under var/broker/ (continuum/filebroker.py), so the quick start
                   runs a real worker (scripts/start starts it) with no broker server to install
SECRET_KEY, DEBUG, ALLOWED_HOSTS
CONTINUUM_*        algorithm defaults where the thesis is ambiguous (see continuum/engine docstrings)
"""

import os
import shlex
from pathlib import Path

import dj_database_url
from kombu import Queue

BASE_DIR = Path(__file__).resolve().parent.parent
VAR_DIR = Path(os.environ.get("CONTINUUM_VAR_DIR", BASE_DIR / "var"))


def env_bool(name: str, default: bool) -> bool:
    value = os.environ.get(name)
    return default if value is None else value.strip().lower() in {"1", "true", "yes", "on"}


DEBUG = env_bool("DEBUG", False)


def _var_secret(name: str, make, directory: Path | None = None) -> str:
    """A random secret kept in <directory, default var/>/<name>, created owner-only (never readable by others,
    not even for a moment) by the first process that needs it; the others read that one."""
    directory = directory or VAR_DIR
    path = directory / name
    if not path.exists():
        directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        # Written whole under a private name, then linked into place: a process starting at the same moment
        # never reads a half-written (empty) secret, and of two writers the first link wins.
        tmp = directory / f".{name}.{os.getpid()}.{os.urandom(4).hex()}"
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(fd, "w") as f:
            f.write(make())
        try:
            os.link(tmp, path)
        except FileExistsError:  # another process of the same server made it just now
            pass
        finally:
            tmp.unlink()
    return path.read_text().strip()


def _secret_key() -> str:
    """SECRET_KEY from the environment, else a random key kept in var/secret_key (never a fixed one)."""
    if os.environ.get("SECRET_KEY"):
        return os.environ["SECRET_KEY"]
    import secrets

    return _var_secret("secret_key", lambda: secrets.token_urlsafe(50))


SECRET_KEY = _secret_key()
# Django's test runner adds "testserver" itself: it is no host a deployment answers to.
ALLOWED_HOSTS = os.environ.get("ALLOWED_HOSTS", "localhost,127.0.0.1,[::1]").split(",")
CSRF_TRUSTED_ORIGINS = [o for o in os.environ.get("CSRF_TRUSTED_ORIGINS", "").split(",") if o]

# ---- Served over HTTPS (README, "Behind a proxy"): CONTINUUM_HTTPS=1 ----------------------------------------
# Plain http is then redirected, browsers are told to use https only (HSTS) and the session and CSRF cookies
# are never sent over plain http. Off by default: the quick start serves http://127.0.0.1.
CONTINUUM_HTTPS = env_bool("CONTINUUM_HTTPS", False)
SECURE_SSL_REDIRECT = CONTINUUM_HTTPS
SESSION_COOKIE_SECURE = CSRF_COOKIE_SECURE = CONTINUUM_HTTPS
SECURE_HSTS_SECONDS = int(os.environ.get("CONTINUUM_HSTS_SECONDS", "31536000")) if CONTINUUM_HTTPS else 0
SECURE_HSTS_INCLUDE_SUBDOMAINS = env_bool("CONTINUUM_HSTS_INCLUDE_SUBDOMAINS", True)
# Preloading is a promise about the whole domain that only its owner can make (and is slow to undo): off unless
# asked for, and `check --deploy` is told that this is deliberate.
SECURE_HSTS_PRELOAD = env_bool("CONTINUUM_HSTS_PRELOAD", False)
SILENCED_SYSTEM_CHECKS = [] if SECURE_HSTS_PRELOAD else ["security.W021"]
SESSION_COOKIE_HTTPONLY = True
SESSION_COOKIE_SAMESITE = CSRF_COOKIE_SAMESITE = "Lax"
SECURE_CONTENT_TYPE_NOSNIFF = True
SECURE_REFERRER_POLICY = "same-origin"
X_FRAME_OPTIONS = "DENY"

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
    "apps.ui",
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
    "auditlog",  # the audit trail (AUDITLOG_* below)
]

MIDDLEWARE = [
    "apps.tenancy.audit.RequestIdMiddleware",
    "continuum.web_metrics.RequestMetricsMiddleware",  # /metrics: requests by route (README "Metrics")
    "apps.tenancy.headers.ContentSecurityPolicyMiddleware",
    # Bodies above their endpoint's limit are refused before anything reads them (its process_view runs
    # before the CSRF middleware's, which reads form bodies).
    "apps.tenancy.bounds.BodyLimitMiddleware",
    "django.middleware.security.SecurityMiddleware",
    "whitenoise.middleware.WhiteNoiseMiddleware",
    # ---- Response compression (issue 13: a 1000 x 10 schedule page was 5.5 MB of HTML) -------------------
    # Near the top, so that it compresses last, after every middleware below that reads or changes the body;
    # WhiteNoise above answers static files itself (see STORAGES for its compressed copies) before reaching it.
    # BREACH: compressing pages that carry a secret and reflect user input can leak the secret by length.
    # Django masks the CSRF token with a fresh random mask on every response (since 1.10), and since 4.2 this
    # middleware also pads each gzip response with up to 100 random bytes ("Heal The Breach"), so it is safe
    # for the dashboard's HTML and the API's JSON. Already-compressed bodies (a tar.gz) are left alone:
    # the middleware keeps the original whenever gzip does not make it smaller.
    "django.middleware.gzip.GZipMiddleware",
    "django.contrib.sessions.middleware.SessionMiddleware",
    "django.middleware.common.CommonMiddleware",
    "apps.tenancy.bounds.RejectNulMiddleware",
    "django.middleware.csrf.CsrfViewMiddleware",
    "django.contrib.auth.middleware.AuthenticationMiddleware",
    "apps.tenancy.audit.AuditMiddleware",  # django-auditlog's, with the client address of clientaddr.py
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
    # ---- SQLite under concurrent writers (the quick start serves many robots) ------------------------
    # WAL: readers never wait for the writer. IMMEDIATE: a transaction takes the write lock when it begins,
    # so two writers queue on the busy timeout instead of one failing with "database is locked" when it
    # upgrades a read lock (SQLite cannot wait there). synchronous=NORMAL is durable in WAL mode except
    # for the last commits on power loss.
    DATABASES["default"]["OPTIONS"] = {
        "init_command": "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;",
        "transaction_mode": "IMMEDIATE",
        "timeout": 20,
    }
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
VAR_DIR.mkdir(mode=0o700, parents=True, exist_ok=True)  # database and secret key: the owner's only
STATIC_ROOT.mkdir(parents=True, exist_ok=True)  # whitenoise warns about a missing root
# Serve static files (plotly.js included) from the app itself, also with DEBUG off; no CDN.
WHITENOISE_USE_FINDERS = True
# CONTINUUM_STATIC_MANIFEST=1 (scripts/start sets it, and runs `collectstatic` with it first): serve the
# collected copies gzipped, under content-hashed names with far-future cache headers. Off by default: a
# template would fail on a file missing from a stale or absent manifest.
if env_bool("CONTINUUM_STATIC_MANIFEST", False):
    STORAGES = {
        "default": {"BACKEND": "django.core.files.storage.FileSystemStorage"},
        "staticfiles": {"BACKEND": "whitenoise.storage.CompressedManifestStaticFilesStorage"},
    }
    WHITENOISE_USE_FINDERS = False  # the finders' copies would shadow the compressed collected ones

# Reverse proxies in front of gunicorn that append the client's address to X-Forwarded-For (README, "Behind a
# proxy"). 0, the default: the header is ignored, the client is the connection's address. The throttles, the
# login limiter and the audit trail all read the client's address through apps/tenancy/clientaddr.py.
CONTINUUM_NUM_PROXIES = int(os.environ.get("CONTINUUM_NUM_PROXIES", "0"))

# A proxy that terminates TLS says so in X-Forwarded-Proto; believed only when proxies are declared.
if CONTINUUM_NUM_PROXIES > 0:
    SECURE_PROXY_SSL_HEADER = ("HTTP_X_FORWARDED_PROTO", "https")

# Content-Security-Policy of every response (apps/tenancy/headers.py): scripts and style sheets from this
# server only, no inline script. 'unsafe-eval' is Plotly's need: its WebGL traces (regl: the large schedules'
# and DAGs' charts) compile their draw calls with Function(); without it they draw nothing and never hover
# (tests/scheduling/test_schedule_browser.py); plotly.js's "strict" bundle would drop that need. Injected
# markup still cannot run a script. Style *attributes* stay allowed (style-src-attr): the pages' meters and
# Plotly set widths and positions with them; an attribute cannot load or select anything. Plotly adds its
# global CSS rules to the (empty) sheet base.html links as "plotly.js-style-global" instead of a style
# element. CONTINUUM_CSP replaces the whole policy.
CONTINUUM_CSP = os.environ.get("CONTINUUM_CSP") or "; ".join(
    [
        "default-src 'self'",
        "script-src 'self' 'unsafe-eval'",
        "style-src 'self'",
        "style-src-attr 'unsafe-inline'",
        "img-src 'self' data: blob:",
        "font-src 'self' data:",
        "connect-src 'self'",
        "worker-src 'self' blob:",
        "object-src 'none'",
        "base-uri 'self'",
        "form-action 'self'",
        "frame-ancestors 'none'",
    ]
)
# ReDoc (/api/redoc/) builds its styles as <style> elements at run time (styled-components): its page alone
# may use inline style elements.
CONTINUUM_CSP_INLINE_STYLE_PATHS = ("/api/redoc/",)

REST_FRAMEWORK = {
    "DEFAULT_AUTHENTICATION_CLASSES": [
        "apps.tenancy.authentication.FleetTokenAuthentication",
        "rest_framework.authentication.SessionAuthentication",
    ],
    "DEFAULT_PERMISSION_CLASSES": [
        "rest_framework.permissions.IsAuthenticated",
        "apps.tenancy.permissions.TokenScopePermission",
    ],
    # Rates per token (or session user), per address without credentials, and per view scope (the robots'
    # report and event endpoints: throttle_scope = "reports"). Counted in CACHES["default"].
    "DEFAULT_THROTTLE_CLASSES": [
        "apps.tenancy.throttling.TokenRateThrottle",
        "apps.tenancy.throttling.ScopedTokenThrottle",
        "apps.tenancy.throttling.AnonymousRateThrottle",
    ],
    "DEFAULT_THROTTLE_RATES": {
        "user": os.environ.get("CONTINUUM_THROTTLE_TOKEN", "20000/min"),
        "reports": os.environ.get("CONTINUUM_THROTTLE_REPORTS", "300000/min"),
        "anon": os.environ.get("CONTINUUM_THROTTLE_ANON", "600/min"),
    },
    "DEFAULT_FILTER_BACKENDS": [
        "apps.tenancy.filters.FleetScopedFilterBackend",  # django-filter, fleet-scoped
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
    # How many proxies in front of the server append to X-Forwarded-For (apps/tenancy/clientaddr.py).
    "NUM_PROXIES": CONTINUUM_NUM_PROXIES,
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
    "ENUM_NAME_OVERRIDES": {
        "AlgorithmEnum": "apps.scheduling.serializers.ALGORITHM_CHOICES",
        "JobStateEnum": "apps.jobs.models.Job.State",
    },
    # Operations tagged and named by resource ("jobs", "jobs_retrieve"), not all under "v1" ("v1_jobs_retrieve"):
    # the docs group them by resource and the generated client (continuum/client/) has usable names.
    "SCHEMA_PATH_PREFIX": r"/api/v[0-9]+",
}

# ---- Celery ---------------------------------------------------------------------------------------
CELERY_BROKER_URL = os.environ.get("CELERY_BROKER_URL", "")
CELERY_BROKER_TRANSPORT_OPTIONS: dict = {}
if not CELERY_BROKER_URL:
    # The quick start: no broker server, messages are files under var/broker/ (continuum/filebroker.py: kombu's
    # filesystem transport with atomic writes and takes, and broken files quarantined instead of crashing the
    # worker), consumed by the workers that scripts/start runs beside the web server. Web and workers share
    # the directory as they share the database.
    BROKER_DIR = Path(os.environ.get("CONTINUUM_BROKER_DIR") or VAR_DIR / "broker")
    for _sub in ("queue", "control", "processed", "quarantine"):
        (BROKER_DIR / _sub).mkdir(mode=0o700, parents=True, exist_ok=True)
    CELERY_BROKER_URL = "continuumfs://"
    CELERY_BROKER_TRANSPORT_OPTIONS = {
        "data_folder_in": str(BROKER_DIR / "queue"),
        "data_folder_out": str(BROKER_DIR / "queue"),
        "control_folder": str(BROKER_DIR / "control"),
        "processed_folder": str(BROKER_DIR / "processed"),
        "quarantine_folder": str(BROKER_DIR / "quarantine"),
        "store_processed": False,
        "polling_interval": 0.2,  # seconds between two looks at the queue directory when it is empty
    }
# CONTINUUM_JOBS_EAGER=1 runs every job inside the process that starts it (its web request or command), with
# the same record, progress and errors: only for tests that ask for it (tests/conftest.py). Never the default.
CELERY_TASK_ALWAYS_EAGER = os.environ.get("CONTINUUM_JOBS_EAGER", "") == "1"
CELERY_TASK_EAGER_PROPAGATES = False
CELERY_TASK_DEFAULT_QUEUE = os.environ.get("CELERY_QUEUE", "continuum")
# RT-Kube's reconcile (an eviction on the clock, thesis Eq. 3.19) has a queue of its own, so that it never waits
# behind a long job: a worker started without -Q consumes both queues; production runs a dedicated one,
# `celery -A continuum worker -Q continuum-rt -P threads -c 8` (docker-compose.yml: rt-worker), whose threads keep
# each cluster's Kubernetes client and its TLS connection warm between evictions (apps/realtime/tasks.py).
CONTINUUM_RT_QUEUE = os.environ.get("CONTINUUM_RT_QUEUE") or f"{CELERY_TASK_DEFAULT_QUEUE}-rt"
# The periodic safety sweeps (beat's tasks: RT taints lifted, overdue violations reconciled, lost jobs and lost
# messages recovered) have a queue of their own too, consumed by a worker of its own (docker-compose.yml:
# sweeper; scripts/start runs one): behind a backlog of jobs they waited 18 minutes (issue 25).
CONTINUUM_SWEEP_QUEUE = os.environ.get("CONTINUUM_SWEEP_QUEUE") or f"{CELERY_TASK_DEFAULT_QUEUE}-sweeps"
CELERY_TASK_QUEUES = (Queue(CELERY_TASK_DEFAULT_QUEUE), Queue(CONTINUUM_RT_QUEUE), Queue(CONTINUUM_SWEEP_QUEUE))
CELERY_TASK_ROUTES = {"continuum.rt_reconcile": {"queue": CONTINUUM_RT_QUEUE},
                      "continuum.rt_warm": {"queue": CONTINUUM_RT_QUEUE},
                      "continuum.rt_lift_taints": {"queue": CONTINUUM_SWEEP_QUEUE},
                      "continuum.rt_reconcile_overdue": {"queue": CONTINUUM_SWEEP_QUEUE},
                      "continuum.recover_lost_jobs": {"queue": CONTINUUM_SWEEP_QUEUE}}  # fmt: skip
CELERY_TASK_ACKS_LATE = True
CELERY_TASK_REJECT_ON_WORKER_LOST = True
CELERY_WORKER_PREFETCH_MULTIPLIER = 1
CELERY_TASK_SERIALIZER = "json"
CELERY_ACCEPT_CONTENT = ["json"]
CELERY_RESULT_BACKEND = None
# Acknowledgement and redelivery: a job's message is acknowledged late, when the job ends (acks_late), so a
# worker that dies mid-job (SIGKILL, out of memory, power) leaves it unacknowledged, and Redis delivers it
# again only after the visibility timeout. That timeout must exceed the longest job: a message held longer
# is delivered a second time while the first run goes on (run_job then waits for that run). A lost worker
# is noticed sooner by the jobs' heartbeats (CONTINUUM_JOB_* below).
CELERY_BROKER_TRANSPORT_OPTIONS |= {
    "visibility_timeout": int(os.environ.get("CELERY_VISIBILITY_TIMEOUT", 3600)),
    "unacked_restore_interval": int(os.environ.get("CELERY_RESTORE_INTERVAL", 10)),
    "unacked_restore_throttle": int(os.environ.get("CELERY_RESTORE_THROTTLE", 10)),
}
CELERY_BROKER_CONNECTION_RETRY_ON_STARTUP = True
# A worker outlives a broker outage of any length (Celery's default gives up after 100 attempts, about 50 minutes,
# and the worker exits): it reconnects when the broker is back, and the jobs wait in the database meanwhile.
CELERY_BROKER_CONNECTION_MAX_RETRIES = None
# Celery's Django fix-up closes a worker thread's database connections before and after EVERY task unless told to
# reuse them: each RT-Kube eviction (continuum.rt_reconcile) then opened a new PostgreSQL connection on the clock.
# Reused for this many tasks instead; a stale or broken one is still retired before each task as Django retires
# it between requests (CONN_MAX_AGE, errors: continuum/celery.py, close_old_connections).
CELERY_DB_REUSE_MAX = int(os.environ.get("CONTINUUM_DB_REUSE_MAX", "1000"))
# `celery -A continuum beat`: lifts RT-Kube's expired node taints (the rt_scheduler process does it too).
CELERY_BEAT_SCHEDULE = {"rt-lift-taints": {"task": "continuum.rt_lift_taints", "schedule": 5.0}}
# A reported violation is stored in the request and reconciled by the continuum.rt_reconcile task; one whose
# message never ran (broker down, worker lost) is reconciled by this sweep once it is this many seconds old.
CONTINUUM_RT_RECONCILE_OVERDUE_S = float(os.environ.get("CONTINUUM_RT_RECONCILE_OVERDUE_S", "30"))
CELERY_BEAT_SCHEDULE["rt-reconcile-overdue"] = {"task": "continuum.rt_reconcile_overdue", "schedule": 10.0}

# ---- Jobs whose worker is gone (apps/jobs/liveness.py) -----------------------------------------------
# A worker's run stamps Job.heartbeat every CONTINUUM_JOB_HEARTBEAT_S seconds. Every CONTINUUM_JOB_CHECK_S
# a thread of each worker (and the beat task below) calls a run lost when its process (on the checker's
# host) is gone or it has been silent for CONTINUUM_JOB_STALE_S, and queues the job again, failing it after
# CONTINUUM_JOB_MAX_ATTEMPTS attempts ("worker lost: no heartbeat since ..."). Job reads in the API check
# too (the quick start runs no worker). Worst case from the last heartbeat: STALE_S + CHECK_S = 45 s.
CONTINUUM_JOB_HEARTBEAT_S = float(os.environ.get("CONTINUUM_JOB_HEARTBEAT_S", "10"))
CONTINUUM_JOB_STALE_S = float(os.environ.get("CONTINUUM_JOB_STALE_S", "30"))
CONTINUUM_JOB_CHECK_S = float(os.environ.get("CONTINUUM_JOB_CHECK_S", "15"))
CONTINUUM_JOB_MAX_ATTEMPTS = int(os.environ.get("CONTINUUM_JOB_MAX_ATTEMPTS", "3"))
CELERY_BEAT_SCHEDULE["jobs-recover-lost"] = {"task": "continuum.recover_lost_jobs", "schedule": CONTINUUM_JOB_CHECK_S}
# A sweep message not run within its period is dropped (the next one does the same work): a sweeper that was
# down does not find a pile of them when it comes back.
for _entry in CELERY_BEAT_SCHEDULE.values():
    _entry.setdefault("options", {"expires": float(_entry["schedule"])})
# Pending jobs (apps/jobs/dispatch.py): a job queued this long ago whose message the queue no longer holds (a
# broker restarted empty, or down when the job was recorded) gets its message again at the next check (so
# within RESEND_AFTER_S + CHECK_S = 35 s); one no worker picked up for PICKUP_WARN_S says so (page and API).
CONTINUUM_JOB_RESEND_AFTER_S = float(os.environ.get("CONTINUUM_JOB_RESEND_AFTER_S", "20"))
CONTINUUM_JOB_PICKUP_WARN_S = float(os.environ.get("CONTINUUM_JOB_PICKUP_WARN_S", "60"))

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
# Prometheus: /metrics on the web app only with this token, only to `Authorization: Bearer <token>` (README
# "Metrics"); CONTINUUM_METRICS_PORT serves the other processes' (continuum/metrics.py).
CONTINUUM_METRICS_TOKEN = os.environ.get("CONTINUUM_METRICS_TOKEN", "").strip()
if CONTINUUM_METRICS_TOKEN and len(CONTINUUM_METRICS_TOKEN) < 16:
    from django.core.exceptions import ImproperlyConfigured

    raise ImproperlyConfigured("CONTINUUM_METRICS_TOKEN must have at least 16 characters (a guessable one is none)")
CONTINUUM_REMAP_THRESHOLD = float(os.environ.get("CONTINUUM_REMAP_THRESHOLD", "0.2"))
# Placement of ROS containers (thesis Table 4.26, continuum/engine/containers/robot_pinning.py): containers holding
# driver-level ROS nodes stay on the nodes labelled CONTINUUM_ROBOT_LABEL unless the operator unpins them
# (a placement request's drivers_on_robot/robot_label override these defaults).
CONTINUUM_DRIVERS_ON_ROBOT = os.environ.get("CONTINUUM_DRIVERS_ON_ROBOT", "1").lower() not in ("0", "false", "off")
CONTINUUM_ROBOT_LABEL = os.environ.get("CONTINUUM_ROBOT_LABEL", "zone=robot")
# The CPU and memory a ROS node asks for when it was not profiled (continuum/engine/containers/resource_model.py,
# a proposal: the thesis prints no per-node model). A JSON object overriding any of its parameters, e.g.
# {"per_message_us": 40, "process_mib": 30}; checked at start-up (containers.E001).
CONTINUUM_RESOURCE_MODEL = os.environ.get("CONTINUUM_RESOURCE_MODEL", "{}")
# ROS nodes into containers (continuum/engine/containers/ros_clustering.py): "refined" (Listing 3.20 then
# Kernighan-Lin/Fiduccia-Mattheyses refinement under Listing 3.20's container-size bound) or "thesis"
# (Listing 3.20 alone). Checked at start-up (containers.E002).
CONTINUUM_ROS_CLUSTERING = os.environ.get("CONTINUUM_ROS_CLUSTERING", "refined")
# ---- Limits (continuum/engine/core/limits.py; README "Limits"; CONTINUUM_MAX_<NAME> overrides) -----------
from continuum.engine.core import limits as _limits  # noqa: E402

CONTINUUM_LIMITS = _limits.get()
# Largest request body (JSON documents) and largest uploaded file (the import endpoints check each file's
# size against the same number, since Django's limit leaves file parts out).
# The body of a document action may be 64 KiB above it (its multipart framing: apps/tenancy/bounds.py,
# UPLOAD_FRAMING_BYTES); the per-endpoint limits (BodyLimitMiddleware) are checked before this one.
DATA_UPLOAD_MAX_MEMORY_SIZE = CONTINUUM_LIMITS.upload_bytes + 64 * 1024
# Files above this are spooled to a temporary file instead of memory while they are read.
FILE_UPLOAD_MAX_MEMORY_SIZE = 2_621_440
# Celery: a job past the soft limit fails with "time limit of N s exceeded"; the hard limit kills the
# worker child; a child above the memory limit (KiB, resident) is replaced after its current job.
CELERY_TASK_SOFT_TIME_LIMIT = int(os.environ.get("CONTINUUM_JOB_SOFT_TIME_LIMIT", 600))
CELERY_TASK_TIME_LIMIT = int(os.environ.get("CONTINUUM_JOB_TIME_LIMIT", CELERY_TASK_SOFT_TIME_LIMIT + 60))
CELERY_WORKER_MAX_MEMORY_PER_CHILD = int(os.environ.get("CONTINUUM_WORKER_MAX_MEMORY_KIB", 2 * 1024 * 1024))
# Address-space cap of each prefork worker child (MiB, 0: none): a job past it fails with that reason.
# Monitor allocations stop on their work budget; this wall-clock cap (s) only catches a solve whose root work
# the budget does not bound (apps/verification/services.py solve_budget). Below the job's soft time limit.
CONTINUUM_MILP_SAFETY_CAP_S = float(os.environ.get("CONTINUUM_MILP_SAFETY_CAP_S", "300"))
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
# A handler that has not reported for this many seconds is not live: no monitor is placed on it (3 stats
# periods, spec 03 §9).
CONTINUUM_HANDLER_LIVENESS_S = float(os.environ.get("CONTINUUM_HANDLER_LIVENESS_S", "3"))
# A handler silent for this many seconds is gone: its monitors start afresh elsewhere. Between the two it is
# late (busy, descheduled) and keeps its monitors; the handlers' coordinator uses the same figure
# (`--dead-after`).
CONTINUUM_HANDLER_GONE_AFTER_S = float(os.environ.get("CONTINUUM_HANDLER_GONE_AFTER_S", "10"))

# ---- Trust boundary: cache, rate limits, audit trail ----------------------------------------------------
# The cache the rate limits count in. Several processes (gunicorn workers) must share it: set
# CONTINUUM_CACHE_URL=redis://host:6379/1 in production. Unset: each process counts on its own (quick start).
if os.environ.get("CONTINUUM_CACHE_URL"):
    CACHES = {
        "default": {
            "BACKEND": "django.core.cache.backends.redis.RedisCache",
            "LOCATION": os.environ["CONTINUUM_CACHE_URL"],
            "KEY_PREFIX": os.environ.get("CONTINUUM_CACHE_PREFIX", "continuum"),
        }
    }
else:
    CACHES = {"default": {"BACKEND": "django.core.cache.backends.locmem.LocMemCache", "LOCATION": "continuum"}}
# Unknown API token keys an address may send per period before it gets 429s (key guessing).
# Seconds a process keeps a robot token it looked up (0: never); revocation: apps/tenancy/authentication.py.
CONTINUUM_ROBOT_TOKEN_CACHE_S = float(os.environ.get("CONTINUUM_ROBOT_TOKEN_CACHE_S", "2"))
CONTINUUM_THROTTLE_BAD_TOKENS = os.environ.get("CONTINUUM_THROTTLE_BAD_TOKENS", "60/min")
# Failed logins (dashboard and admin) per address and user name within the window before the form refuses.
CONTINUUM_LOGIN_FAILURES = int(os.environ.get("CONTINUUM_LOGIN_FAILURES", "10"))
CONTINUUM_LOGIN_WINDOW_S = int(os.environ.get("CONTINUUM_LOGIN_WINDOW_S", "900"))
# Audit trail (django-auditlog, in the admin): the models people configure, not the high-volume rows robots
# write (reports, events, verdicts) nor the jobs (recorded anyway). Big derived documents are left out.
AUDITLOG_CID_GETTER = "apps.tenancy.audit.request_id"
AUDITLOG_DISABLE_REMOTE_ADDR = False
AUDITLOG_INCLUDE_TRACKING_MODELS = tuple(
    {"model": model, "exclude_fields": list(excluded), **extra}
    for model, excluded, extra in [
        ("tenancy.Fleet", (), {"m2m_fields": {"members"}}),
        # Who may do what: accounts (never their password hash), groups and permissions.
        ("auth.User", ("password", "last_login"), {"m2m_fields": {"groups", "user_permissions"}}),
        ("auth.Group", (), {"m2m_fields": {"permissions"}}),
        ("auth.Permission", (), {}),
        ("tenancy.FleetToken", ("key_hash", "last_used"), {}),
        ("clusters.Cluster", ("kubeconfig",), {}),  # secret: the trail says the cluster changed, not how
        ("clusters.ComputeNode", (), {}),
        ("clusters.Link", (), {}),
        ("workloads.Application", ("dag",), {}),
        ("scheduling.Schedule", ("platform", "ranks", "metrics"), {}),
        ("containers.RosGraph", ("document",), {}),
        ("containers.Clustering", ("graph_document", "result", "images"), {}),
        ("containers.Placement", ("containers", "cluster_document", "plan", "baseline"), {}),
        ("devices.DeviceProfile", (), {}),
        ("realtime.RTPolicy", (), {}),
        ("realtime.RealTime", (), {}),
        ("verification.Assertion", (), {}),
        ("verification.Monitor", ("state", "cpu"), {}),  # runtime state, rewritten by every event batch
    ]
)


# ---- Kubernetes credentials (issue 10, trust boundary; apps/kube/kubeconfig.py, apps/kube/credentials.py) ----
def credentials_key_file(var_dir: Path = VAR_DIR) -> Path:
    """Where the quick start keeps the key of ``var_dir``'s database: CONTINUUM_CREDENTIALS_KEY_FILE, else
    ``$XDG_CONFIG_HOME/continuum/keys/<hash of var_dir>.key`` (``~/.config``). Never inside var/: a copy of
    the database (a backup, a tarball of var/) must not carry the key that decrypts its kubeconfigs (issue 25).
    One key per var/ directory, so that two checkouts never share (or take over) each other's."""
    if os.environ.get("CONTINUUM_CREDENTIALS_KEY_FILE"):
        return Path(os.environ["CONTINUUM_CREDENTIALS_KEY_FILE"])
    import hashlib

    config = Path(os.environ.get("XDG_CONFIG_HOME") or Path.home() / ".config")
    tag = hashlib.sha256(str(var_dir.resolve()).encode()).hexdigest()[:16]
    return config / "continuum" / "keys" / f"{tag}.key"


def _credentials_keys() -> list[str]:
    """Fernet keys that encrypt kubeconfigs at rest: CONTINUUM_CREDENTIALS_KEY (comma-separated, newest first,
    for rotation), else a random key kept 0600 in :func:`credentials_key_file`, apart from the database. Web
    and worker must share it. A key an older version kept in var/credentials_key is moved there."""
    if os.environ.get("CONTINUUM_CREDENTIALS_KEY"):
        return [k.strip() for k in os.environ["CONTINUUM_CREDENTIALS_KEY"].split(",") if k.strip()]
    import base64

    path = credentials_key_file()
    old = VAR_DIR / "credentials_key"
    # A Fernet key: 32 random bytes, URL-safe base64; or the one an older version kept beside the database.
    made = old.read_text if old.exists() else lambda: base64.urlsafe_b64encode(os.urandom(32)).decode()
    key = _var_secret(path.name, made, path.parent)
    if old.exists() and old.read_text().strip() == key:
        old.unlink(missing_ok=True)  # moved, not copied: only the config directory holds it now
    return [key]


CONTINUUM_CREDENTIALS_KEYS = _credentials_keys()
# Plain http to a Kubernetes API is refused (it would expose the credentials), except on a loopback address
# when this is on (tests, a local kind/k3d cluster).
CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK = env_bool("CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK", False)
# Comma-separated host names (api.example.org, *.example.org) and IP networks (10.0.0.0/8) a kubeconfig's
# server may name; empty: any host. Names are compared as written, never resolved.
CONTINUUM_KUBE_API_ALLOWED_HOSTS = [
    h.strip() for h in os.environ.get("CONTINUUM_KUBE_API_ALLOWED_HOSTS", "").split(",") if h.strip()
]
CONTINUUM_KUBECONFIG_MAX_BYTES = int(os.environ.get("CONTINUUM_KUBECONFIG_MAX_BYTES", 64 * 1024))
# The gateway retries a transient failure (connection error, 429, 5xx) of an idempotent call with exponential
# backoff and jitter from RETRY_BASE_S until RETRY_DEADLINE_S has passed, then fails naming the call.
CONTINUUM_KUBE_RETRY_DEADLINE_S = float(os.environ.get("CONTINUUM_KUBE_RETRY_DEADLINE_S", "30"))
CONTINUUM_KUBE_RETRY_BASE_S = float(os.environ.get("CONTINUUM_KUBE_RETRY_BASE_S", "0.2"))
# A push (a schedule's pods, a placement's Deployments) has at most this many API calls in flight (1..64).
CONTINUUM_KUBE_PUSH_CONCURRENCY = int(os.environ.get("CONTINUUM_KUBE_PUSH_CONCURRENCY", "8"))
