# Shared by scripts/start and scripts/test: a virtualenv, and the real servers the tests need.
# Each ensure_* function uses what the machine already runs and installs/starts what is missing.
# Sourced, not run. Servers this script starts listen on loopback only and keep their data under $VAR.

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
VAR=${CONTINUUM_VAR_DIR:-$ROOT/var}
mkdir -p "$VAR"

say() { echo "[continuum] $*" >&2; }

private_var() {  # var/ holds the database, the secret key and the demo credentials: the owner's only
  umask 077           # what is created from now on (SQLite's -wal and -shm files too)
  chmod -R go= "$VAR"  # what an older version left readable
}
as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }
port_open() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

apt_install() {
  local missing=()
  for p in "$@"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
  [ ${#missing[@]} -eq 0 ] && return 0
  say "installing ${missing[*]} from Debian"
  if [ -z "${APT_UPDATED:-}" ]; then as_root apt-get update -qq >&2; APT_UPDATED=1; fi
  DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq -o DPkg::Lock::Timeout=600 "${missing[@]}" >&2
}

ensure_venv() {  # ensure_venv requirements-file
  local req=$1 stamp tstamp
  PY=${PYTHON:-python3}
  if [ ! -x "$ROOT/.venv/bin/python" ]; then
    say "creating .venv"
    "$PY" -m venv "$ROOT/.venv" || { apt_install python3-venv && "$PY" -m venv "$ROOT/.venv"; }
  fi
  # requirements-robot.txt (the fleet client's, included by requirements-test.txt) is hashed too.
  stamp="$ROOT/.venv/.installed-$(cat "$ROOT/requirements.txt" "$ROOT/requirements-robot.txt" "$ROOT/$req" | sha256sum | cut -c1-16)"
  # The test requirements include the runtime ones: a venv that scripts/test made serves scripts/start too.
  tstamp="$ROOT/.venv/.installed-$(cat "$ROOT/requirements.txt" "$ROOT/requirements-robot.txt" "$ROOT/requirements-test.txt" | sha256sum | cut -c1-16)"
  if [ ! -f "$stamp" ] && [ ! -f "$tstamp" ]; then
    say "installing Python packages from $req"
    "$ROOT/.venv/bin/python" -m pip install -q --upgrade pip >&2
    "$ROOT/.venv/bin/python" -m pip install -q -r "$ROOT/$req" >&2
    touch "$stamp"
  fi
  export PATH="$ROOT/.venv/bin:$PATH"
}

ensure_postgres() {  # sets DATABASE_URL
  if port_open 5432; then
    export DATABASE_URL=${DATABASE_URL:-postgres://postgres@127.0.0.1:5432/continuum}
    return 0
  fi
  local port=55432 data=/tmp/continuum-pg
  if ! port_open $port; then
    apt_install postgresql
    local bin; bin=$(ls -d /usr/lib/postgresql/*/bin | sort -V | tail -1)
    if [ ! -f "$data/PG_VERSION" ]; then
      say "creating a PostgreSQL cluster in $data"
      as_root mkdir -p "$data"; as_root chown postgres: "$data"
      as_root su postgres -s /bin/sh -c "$bin/initdb -D $data -U postgres --auth=trust >/dev/null"
    fi
    say "starting PostgreSQL on 127.0.0.1:$port"
    as_root su postgres -s /bin/sh -c "$bin/pg_ctl -D $data -l $data/server.log -w \
      -o '-p $port -c listen_addresses=127.0.0.1 -k /tmp' start >/dev/null"
  fi
  export DATABASE_URL=${DATABASE_URL:-postgres://postgres@127.0.0.1:$port/continuum}
}

ensure_redis() {  # sets REDIS_URL
  if port_open 6379; then export REDIS_URL=${REDIS_URL:-redis://127.0.0.1:6379}; return 0; fi
  local port=56379
  if ! port_open $port; then
    apt_install redis-server
    say "starting Redis on 127.0.0.1:$port"
    redis-server --daemonize yes --bind 127.0.0.1 --port $port --save "" --appendonly no \
      --dir /tmp --logfile "$VAR/redis.log" >/dev/null
    for _ in $(seq 50); do port_open $port && break; sleep 0.1; done
  fi
  export REDIS_URL=${REDIS_URL:-redis://127.0.0.1:$port}
}

ensure_chromium() {
  [ -x /usr/bin/chromium ] || apt_install chromium
}

ensure_ros1() {  # Debian's ROS 1: a real roscore, rospy (for /usr/bin/python3), rosbag, rostopic (tests/ros/)
  apt_install ros-core python3-rospy python3-rosbag python3-rostopic python3-std-msgs
}

ensure_kube_apiserver() {  # builds (or takes from the cache) kube-apiserver and etcd
  KUBE_APISERVER=$(bash "$ROOT/scripts/build-kube-apiserver.sh")
  export KUBE_APISERVER
}

ensure_kube_binaries() {  # builds (or takes from the cache) kube-apiserver, -controller-manager, -scheduler, kubemark
  say "Kubernetes binaries (the first build takes about 22 minutes on 2 busy cores; cached in ~/.cache/continuum)"
  KUBE_BIN_DIR=$(bash "$ROOT/scripts/build-kube.sh" | tail -n1)
  export KUBE_BIN_DIR
}

ensure_real_node_packages() {  # real nodes ("runtime": "real"): containerd, runc, CNI plugins; images: debootstrap, buildah
  [ "$(id -u)" = 0 ] || return 0  # real nodes need root (the tests that use them say why they skip)
  apt_install containerd runc containernetworking-plugins debootstrap buildah
}
