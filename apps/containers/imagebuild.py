"""Images built for real, by inheritance (thesis 3.2.1, Table 4.16 from images): buildah on this machine.

The plan (:mod:`continuum.engine.containers.debian_images`) is built parent first, each image ``FROM`` its
parent; then every image's layers are read from buildah's storage (``diff-size`` of each layer, uncompressed,
as they sit on a node's disk) and the disk figures are measured the way the planner predicts them:

* before: every container image alone (its full size: base + parents + its own layer);
* after: one device holding them all (the base once, every image's own layers once).

Builds use buildah's chroot isolation, not runc: runc gives each RUN a cgroup with the machine's CPU set, which
the kernel refuses while a cluster with real nodes holds every CPU in an exclusive cpuset (measured: "did not get
container create message from subprocess: EOF"); a build needs no cgroup of its own.

The planner's prediction is made from figures known before anything is built: the base image's measured size
and each Debian package's ``Installed-Size`` with its dependencies that the base does not have (``apt-cache
depends --recurse``), which is the model's input (it adds package sizes; apt shares dependencies between
packages of one image, which the model counts once per package).
"""

from __future__ import annotations

import json
import re
import subprocess
import tempfile
import time
import uuid
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

from continuum.engine.containers.debian_images import BASE_IMAGE, build_steps
from continuum.engine.containers.image_inheritance import ImagePlan, plan_images, reduction

#: Table 4.16's saving as the thesis prints it (its totals), for the page and the report only.
THESIS_SAVED = 0.832
STORAGE = Path("/var/lib/containers/storage")
MIB = 1024 * 1024


class BuildError(RuntimeError):
    """A buildah or apt step failed (the message ends with its stderr's last lines)."""


#: runc failing to start a container's init (seen once in a loaded test run, "did not get container create message
#: from subprocess: EOF"): the same command is tried once more.
TRANSIENT = "did not get container create message"


def _run(args: list[str], timeout: float = 1800) -> str:
    for attempt in range(2):
        try:
            proc = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
        except FileNotFoundError as exc:
            raise BuildError(f"{args[0]} is not installed (Debian: apt-get install buildah)") from exc
        except subprocess.TimeoutExpired as exc:
            raise BuildError(f"{' '.join(args[:3])} did not finish in {timeout:.0f} s") from exc
        if proc.returncode == 0 or TRANSIENT not in proc.stderr or attempt:
            break
    if proc.returncode != 0:
        tail = " | ".join(proc.stderr.strip().splitlines()[-3:])
        raise BuildError(f"{' '.join(args[:3])} failed ({proc.returncode}): {tail}")
    return proc.stdout


def layer_sizes() -> dict[str, int]:
    """Every layer in buildah's storage: uncompressed digest -> bytes."""
    out: dict[str, int] = {}
    for driver in ("overlay", "vfs"):
        path = STORAGE / f"{driver}-layers" / "layers.json"
        if path.exists():
            for layer in json.loads(path.read_text() or "[]"):
                if layer.get("diff-digest") and layer.get("diff-size") is not None:
                    out[layer["diff-digest"]] = int(layer["diff-size"])
    return out


def image_layers(reference: str) -> list[str]:
    doc = json.loads(_run(["buildah", "inspect", "--type", "image", reference], timeout=120))
    return list(((doc.get("OCIv1") or {}).get("rootfs") or {}).get("diff_ids") or [])


def base_packages(base: str) -> set[str]:
    """The Debian packages installed in the base image."""
    container = _run(["buildah", "from", "--pull-never", base], timeout=300).strip().splitlines()[-1]
    try:
        text = _run(
            ["buildah", "run", "--isolation", "chroot", container, "--", "dpkg-query", "-W", "-f", "${Package}\\n"],
            timeout=300,
        )
    finally:
        subprocess.run(["buildah", "rm", container], capture_output=True, timeout=120)
    return {line.strip() for line in text.splitlines() if line.strip()}


def _closure(package: str) -> set[str]:
    text = _run(["apt-cache", "depends", "--recurse", "--no-recommends", "--no-suggests", "--no-conflicts",
                 "--no-breaks", "--no-replaces", "--no-enhances", package], timeout=300)  # fmt: skip
    return {line.split(":")[0] for line in text.splitlines() if line and not line.startswith((" ", "<"))}


def _installed_kib(packages: Iterable[str]) -> dict[str, int]:
    names = sorted(packages)
    if not names:
        return {}
    text = _run(["apt-cache", "show", "--no-all-versions", *names], timeout=300)
    out, current = {}, None
    for line in text.splitlines():
        if line.startswith("Package: "):
            current = line.split(": ", 1)[1].strip()
        elif line.startswith("Installed-Size: ") and current:
            out[current] = int(re.sub(r"\D", "", line.split(": ", 1)[1]) or 0)
    return out


def predicted_sizes(packages: Iterable[str], in_base: set[str]) -> dict[str, float]:
    """Each package with the dependencies the base lacks, in MiB (apt's Installed-Size): the planner's input."""
    closures = {p: _closure(p) - in_base for p in packages}
    kib = _installed_kib(set().union(*closures.values()) if closures else set())
    return {p: round(sum(kib.get(q, 0) for q in c) / 1024, 3) for p, c in closures.items()}


def predict(deps: Mapping[str, list[str]], base: str = BASE_IMAGE) -> tuple[ImagePlan, float]:
    """The planner's plan and prediction for these containers, from apt's metadata and the base's size."""
    in_base = base_packages(base)
    sizes = layer_sizes()
    base_mib = sum(sizes.get(d, 0) for d in image_layers(base)) / MIB
    packages = sorted({p for pkgs in deps.values() for p in pkgs})
    plan = plan_images(deps, predicted_sizes(packages, in_base), distro_image=base, distro_mib=round(base_mib, 3),
                       platforms=("amd64",), repository="continuum-built")  # fmt: skip
    return plan, base_mib


def build(plan: ImagePlan, progress: Callable[[int, str], None], base: str = BASE_IMAGE, tag: str | None = None
          ) -> dict[str, Any]:  # fmt: skip
    """Build every image of ``plan`` (parents first) and measure them; see the module docstring. Each build has
    its own tag (``tag``, default a fresh one): two builds at once never take each other's parent."""
    tag = tag or f"b{uuid.uuid4().hex[:12]}"
    try:
        image_layers(base)
    except BuildError as exc:
        raise BuildError(f"no base image {base} in buildah's storage: run scripts/build-images.sh base") from exc
    steps = build_steps(plan, base, tag)
    timings: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="continuum-imagebuild-") as tmp:
        for i, step in enumerate(steps):
            progress(5 + 85 * i // len(steps), f"building {step.image} FROM {step.parent} (+{len(step.packages)} "
                     "Debian packages)")  # fmt: skip
            context = Path(tmp) / step.image
            context.mkdir()
            (context / "Containerfile").write_text(step.containerfile)
            began = time.monotonic()
            _run(["buildah", "bud", "--quiet", "--pull-never", "--layers=false", "--isolation", "chroot", "-t",
                  step.reference, "-f",
                  str(context / "Containerfile"), str(context)], timeout=3600)  # fmt: skip
            timings[step.image] = round(time.monotonic() - began, 1)
    progress(92, "measuring the layers")
    sizes = layer_sizes()
    base_layers = image_layers(base)
    layers = {s.image: image_layers(s.reference) for s in steps}
    by_ref = {s.reference: s.image for s in steps}
    images = []
    for step in steps:
        parent_layers = base_layers if step.parent == base else layers[by_ref[step.parent]]
        own = [d for d in layers[step.image] if d not in parent_layers]
        planned = plan.image(step.image)
        images.append({
            "name": step.image, "kind": step.kind, "reference": step.reference, "parent": step.parent,
            "packages": list(step.packages), "build_s": timings[step.image],
            "layers": [{"digest": d, "mib": round(sizes.get(d, 0) / MIB, 3)} for d in layers[step.image]],
            "size_mib": round(sum(sizes.get(d, 0) for d in layers[step.image]) / MIB, 3),
            "own_mib": round(sum(sizes.get(d, 0) for d in own) / MIB, 3),
            "predicted_size_mib": round(planned.size_mib, 3), "predicted_own_mib": round(planned.unique_mib, 3),
        })  # fmt: skip
    base_mib = sum(sizes.get(d, 0) for d in base_layers) / MIB
    before = sum(im["size_mib"] for im in images if im["kind"] == "container")
    after = base_mib + sum(im["own_mib"] for im in images)
    return {
        "base": {"reference": base, "size_mib": round(base_mib, 3),
                 "layers": [{"digest": d, "mib": round(sizes.get(d, 0) / MIB, 3)} for d in base_layers]},
        "images": images,
        "before_mib": round(before, 3),
        "after_mib": round(after, 3),
        "saved": round(reduction(before, after), 4) if before > 0 else 0.0,
        "predicted_before_mib": round(plan.before_mib, 3),
        "predicted_after_mib": round(plan.after_mib, 3),
        "predicted_saved": round(plan.saved, 4),
        "thesis_saved": THESIS_SAVED,
        "tag": tag,
    }  # fmt: skip


def export(reference: str, directory: Path) -> Path:
    """A docker-archive of the image (named ``docker.io/<reference>``, what the CRI looks up), for
    ``ctr -n k8s.io images import`` or ``scripts/cluster import-image``."""
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / (reference.replace("/", "_").replace(":", "_") + ".docker.tar")
    path.unlink(missing_ok=True)
    _run(["buildah", "push", "--quiet", reference, f"docker-archive:{path}:docker.io/{reference}"], timeout=1800)
    return path


def remove(references: Iterable[str]) -> None:
    """Remove built images from buildah's storage, children first (a parent in use stays until they go)."""
    for ref in reversed(list(references)):
        subprocess.run(["buildah", "rmi", ref], capture_output=True, timeout=300)
