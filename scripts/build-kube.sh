#!/usr/bin/env bash
# Builds the rest of a local Kubernetes v1.20.2 offline from Debian bookworm's `kubernetes` source package:
# kube-controller-manager, kube-scheduler, kubemark (whose `--morph=kubelet` is a hollow node: a real
# kubelet with a fake container runtime), the kubelet itself (a real node over containerd, for clusters whose
# nodes say "runtime": "real") and the pause binary of the pod sandbox image (build/pause, never pulled). kube-apiserver comes from scripts/build-kube-apiserver.sh (same
# source, same reflect2/json-iterator swap, its own cache entry, so the tests' apiserver is not rebuilt).
#
# Two small patches make several hollow nodes safe on one machine (upstream runs each in its own pod):
# - the fake container runtime listens on a fixed /tmp/kubelet_remote.sock, so a second hollow node would take
#   over the first one's socket (and its pods); it now listens under $TMPDIR, which scripts/cluster sets per node;
# - the hollow kubelet's API binds 0.0.0.0; it now binds loopback.
#
# Output: $CONTINUUM_CACHE/kube-bin-<hash of this script>/ holding the binaries plus a symlink to the
# apiserver; the directory's path is the last line of stdout. Progress goes to stderr.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
cache="${CONTINUUM_CACHE:-$HOME/.cache/continuum}"
hash=$(sha256sum "$0" | cut -c1-12)
out="$cache/kube-bin-$hash"
bins="kube-controller-manager kube-scheduler kubemark kubelet"
log() { echo "[build-kube] $*" >&2; }

apiserver=$("$here/build-kube-apiserver.sh" | tail -n1)
complete() { for b in $bins kube-apiserver pause; do [ -x "$out/$b" ] || return 1; done; }
if complete; then echo "$out"; exit 0; fi
mkdir -p "$cache"

# build-kube-apiserver.sh installed the toolchain and the deb-src entry. One build at a time; a fixed source
# path keeps Go's build cache (keyed on -trimpath=<source dir>) valid for the next build.
exec 9>"$cache/.build-kube.lock"
flock 9
if complete; then echo "$out"; exit 0; fi
work="${TMPDIR:-/tmp}/continuum-kube-src"
ticker=""
cleanup() { [ -z "$ticker" ] || kill "$ticker" 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
rm -rf "$work"
mkdir -p "$work"
cd "$work"
log "fetching the kubernetes source package"
apt-get source --download-only kubernetes >&2
dpkg-source --no-check -x ./kubernetes_*.dsc src >/dev/null
cd src

# The vendored reflect2 1.0.1 crashes under Go >= 1.18; use Debian's packaged copies (as for the apiserver).
for lib in github.com/modern-go/reflect2 github.com/json-iterator/go; do
  rm -rf "vendor/$lib"
  mkdir -p "vendor/$lib"
  (cd "/usr/share/gocode/src/$lib" && find . -maxdepth 1 -type f \( -name '*.go' -o -name '*.s' \) ! -name '*_test.go' \
     -exec cp {} "$work/src/vendor/$lib/" \;)
done

fake=pkg/kubelet/cri/remote/fake/endpoint.go
sed -i -e 's|^package fake$|package fake\n\nimport "os"|' \
  -e 's|return defaultUnixEndpoint, nil|return "unix://" + os.TempDir() + "/kubelet_remote.sock", nil|' "$fake"
sed -i 's|c.Address = "0.0.0.0"|c.Address = "127.0.0.1"|' pkg/kubemark/hollow_kubelet.go
grep -q 'os.TempDir()' "$fake" && grep -q 'c.Address = "127.0.0.1"' pkg/kubemark/hollow_kubelet.go \
  || { log "the kubemark patches no longer apply to this source"; exit 1; }

for p in gcc libc6-dev; do
  dpkg -s "$p" >/dev/null 2>&1 || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$p" >&2
done
# The pod sandbox's process: static, so the image needs nothing else (build/pause/Dockerfile does the same).
gcc -Os -static -o "$work/pause" build/pause/linux/pause.c

start=$(date +%s)
log "building $bins (cold: about 17 minutes on a busy 2-core machine; Go's build cache makes reruns fast)"
# make is silent for minutes while Go compiles: say that it is still alive.
( while sleep 30; do log "still compiling… $(( $(date +%s) - start )) s"; done ) &
ticker=$!
export GOPROXY=off GOFLAGS=-mod=vendor GO111MODULE=on
what=""
for b in $bins; do what="$what cmd/$b"; done
make WHAT="${what# }" >&2
log "built in $(( $(date +%s) - start )) s"

mkdir -p "$out.tmp"
for b in $bins; do cp "_output/bin/$b" "$out.tmp/$b"; done
cp "$work/pause" "$out.tmp/pause"
ln -sf "$apiserver" "$out.tmp/kube-apiserver"
rm -rf "$out"
mv "$out.tmp" "$out"
echo "$out"
