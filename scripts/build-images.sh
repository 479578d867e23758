#!/usr/bin/env bash
# Container images for real nodes, built on this machine from Debian packages and never pulled (no container
# registry is reachable; Debian's mirror is):
#   build-images.sh base              the base image continuum/base:bookworm: `debootstrap --variant=minbase
#                                     bookworm` -> rootfs.tar -> buildah `FROM scratch` + `ADD rootfs.tar /`
#   build-images.sh pause PAUSE_BIN   the pod sandbox image localhost/pause:3.4.1 from the static pause binary
#                                     that scripts/build-kube.sh compiles from build/pause (KUBE_BIN_DIR/pause)
# Each prints, as its last stdout line, a docker-archive tarball of the image (named docker.io/continuum/base:
# bookworm or localhost/pause:3.4.1, the names the CRI looks up) that `ctr -n k8s.io images import` takes.
# The image also stays in buildah's local storage as localhost/continuum/base:bookworm, so a Containerfile here
# may say `FROM continuum/base:bookworm` (images built by inheritance reuse it).
#
# Cached in $CONTINUUM_CACHE/images (default ~/.cache/continuum/images) under the hash of this script (the
# rootfs tarball, 68 s and about 200 MB, and the archives); one build at a time (flock). Needs root, debootstrap
# and buildah (installed from Debian when missing). Progress goes to stderr.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
# shellcheck source=scripts/services.sh
source "$here/services.sh"
cache="${CONTINUUM_CACHE:-$HOME/.cache/continuum}/images"
hash=$(sha256sum "$0" | cut -c1-12)
log() { echo "[build-images] $*" >&2; }
usage() { echo "usage: build-images.sh base | pause PAUSE_BIN" >&2; exit 2; }

[ "$(id -u)" = 0 ] || { echo "build-images.sh: needs root (debootstrap, buildah's storage)" >&2; exit 2; }
what=${1:-}
case $what in
  base) [ $# = 1 ] || usage ;;
  pause) [ $# = 2 ] && [ -f "$2" ] && [ -x "$2" ] || usage ;;
  *) usage ;;
esac
mkdir -p "$cache"
exec 9>"$cache/.lock"
flock 9
apt_install debootstrap buildah

work=$(mktemp -d "${TMPDIR:-/tmp}/continuum-images.XXXXXX")
trap 'rm -rf "$work"' EXIT

# $1 buildah name, $2 tag in the archive, $3 archive path, $4 label value; stdin: the Containerfile; the context
# is $work/ctx. Builds only when the archive is missing.
build() {
  local name=$1 tag=$2 archive=$3 key=$4
  if [ -s "$archive" ] && [ "$(buildah inspect --type image --format '{{index .OCIv1.Config.Labels "continuum.key"}}' "$name" 2>/dev/null)" = "$key" ]; then
    return 0
  fi
  cat > "$work/ctx/Containerfile"
  log "building $name with buildah"
  buildah bud --quiet --layers=false --label "continuum.key=$key" -t "$name" -f "$work/ctx/Containerfile" "$work/ctx" >&2
  rm -f "$archive.tmp"
  buildah push --quiet "$name" "docker-archive:$archive.tmp:$tag" >&2
  mv "$archive.tmp" "$archive"
}

mkdir -p "$work/ctx"
if [ "$what" = base ]; then
  rootfs="$cache/bookworm-minbase-$hash.tar"
  if [ ! -s "$rootfs" ]; then
    log "debootstrap --variant=minbase bookworm (about a minute and 200 MB; cached in $rootfs)"
    start=$(date +%s)
    debootstrap --variant=minbase bookworm "$work/rootfs" http://deb.debian.org/debian >"$work/debootstrap.log" 2>&1 \
      || { tail -n 20 "$work/debootstrap.log" >&2; exit 1; }
    # The image needs no apt lists or caches (a child image runs apt-get update first).
    rm -rf "$work/rootfs/var/lib/apt/lists/"* "$work/rootfs/var/cache/apt/"*.bin
    tar -C "$work/rootfs" --numeric-owner -cf "$rootfs.tmp" .
    mv "$rootfs.tmp" "$rootfs"
    rm -rf "$work/rootfs"
    log "rootfs built in $(( $(date +%s) - start )) s"
  fi
  archive="$cache/base-bookworm-$hash.docker.tar"
  ln "$rootfs" "$work/ctx/rootfs.tar" 2>/dev/null || cp "$rootfs" "$work/ctx/rootfs.tar"
  build localhost/continuum/base:bookworm docker.io/continuum/base:bookworm "$archive" "$hash" <<'EOF'
FROM scratch
ADD rootfs.tar /
# A pod that gives no command runs a real, idle process (a Deployment pushed with this image stays Running).
CMD ["sleep", "infinity"]
EOF
else
  key="$hash-$(sha256sum "$2" | cut -c1-12)"
  archive="$cache/pause-$key.docker.tar"
  cp "$2" "$work/ctx/pause"
  build localhost/pause:3.4.1 localhost/pause:3.4.1 "$archive" "$key" <<'EOF'
FROM scratch
COPY pause /pause
USER 65535:65535
ENTRYPOINT ["/pause"]
EOF
fi
echo "$archive"
