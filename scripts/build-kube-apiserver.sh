#!/usr/bin/env bash
# Builds kube-apiserver v1.20.2 offline from Debian bookworm's `kubernetes` source package and caches it.
#
# No registry ships kube-apiserver binaries; Debian's source package carries the full upstream tree with
# vendor/, which builds with Debian's Go. The vendored reflect2 1.0.1 crashes under Go >= 1.18 on the
# first custom-object request, so it (and json-iterator) are replaced by Debian's packaged copies.
#
# Output: $CONTINUUM_CACHE/kube-apiserver-<hash of this script> (prints the path on stdout).
set -euo pipefail

cache="${CONTINUUM_CACHE:-$HOME/.cache/continuum}"
hash=$(sha256sum "$0" | cut -c1-12)
out="$cache/kube-apiserver-$hash"
if [ -x "$out" ]; then echo "$out"; exit 0; fi
mkdir -p "$cache"

log() { echo "[build-kube-apiserver] $*" >&2; }
as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

pkgs="etcd-server golang-go make rsync dpkg-dev openssl golang-github-modern-go-reflect2-dev golang-github-json-iterator-go-dev"
missing=""
for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done
if ! grep -rqs "deb-src" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  log "adding deb-src for bookworm"
  as_root tee /etc/apt/sources.list.d/continuum-src.sources >/dev/null <<'SRC'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb-src
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
  need_update=1
fi
if [ -n "$missing" ] || [ -n "${need_update:-}" ]; then
  log "installing:$missing"
  as_root apt-get update -qq >&2
  [ -z "$missing" ] || DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq $missing >&2
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/kube-src.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
log "fetching the kubernetes source package"
apt-get source --download-only kubernetes >&2
dpkg-source --no-check -x ./kubernetes_*.dsc src >&2
cd src

for lib in github.com/modern-go/reflect2 github.com/json-iterator/go; do
  rm -rf "vendor/$lib"
  mkdir -p "vendor/$lib"
  (cd "/usr/share/gocode/src/$lib" && find . -maxdepth 1 -type f \( -name '*.go' -o -name '*.s' \) ! -name '*_test.go' \
     -exec cp {} "$work/src/vendor/$lib/" \;)
done

log "building (about 4 minutes on 2 cores)"
export GOPROXY=off GOFLAGS=-mod=vendor GO111MODULE=on
make WHAT=cmd/kube-apiserver >&2
cp _output/bin/kube-apiserver "$out.tmp"
mv "$out.tmp" "$out"
echo "$out"
