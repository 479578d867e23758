"""Inheritance-based container image generation (thesis 3.2.1, Fig. 3.24, Table 4.16).

Every container image must hold the packages of its ROS nodes (installed via rosdep); packages needed by
several containers would be stored once per image. Docker's layered filesystem lets images share them
instead: the packages of each overlap of the containers' dependency sets (the Venn regions of Fig. 3.24)
go into a parent image, and children inherit it. The spec's algorithm (02, section 3):

1. Each container ``C_i`` has a dependency set ``D_i`` (the union of its ROS nodes' packages).
2. For every package ``p``, ``S(p)`` = the containers that need it; region ``R_S`` = the packages whose
   owner set is exactly ``S``.
3. ``R_all`` (needed by every container) becomes the ``base`` image, ``FROM`` the ROS distribution image.
4. Every region with ``2 <= |S| < k`` becomes an intermediate parent image. An image needs every region
   whose owner set strictly contains its own (for a container: every shared region it belongs to).
5. An image is ``FROM`` the required image with the most bytes (its content = its region + everything it
   needs); any required region not on that ``FROM`` chain is pulled in with a multi-stage build (the
   multiple-inheritance case of ``C2`` in Fig. 3.24).
6. Images are built once, for every target platform (``docker buildx``, linux/amd64, linux/arm64, and
   linux/riscv64 when every package exists there).

Multi-stage copies are exact: each parent image records the files its packages installed
(``/opt/continuum/<image>.files``, from dpkg), and a child copies just those files from a BuildKit bind
mount of the parent stage. The copy is a new layer, so its bytes count again in the disk figures.

Disk accounting (all images on one device): *before* = every container image alone, ``k * distro + sum of
|D_i|``; *after* = the distro once + every region once + the bytes copied by multi-stage builds. Table 4.16
(RB-Kairos) reports 83.2% saved from its printed totals and 81.6% from its rows (spec: the rows do not sum
to the printed totals); :data:`TABLE_4_16` keeps the reference figures.
"""

from __future__ import annotations

import io
import json
import re
import shlex
import tarfile
import zipfile
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.containers.rosgraph import RosGraph, natural_key
from continuum.engine.core import artifact_names
from continuum.engine.core.cluster import normalize_arch
from continuum.engine.core.errors import InputError

__all__ = [
    "DEFAULT_PLATFORMS",
    "TABLE_4_16",
    "TABLE_4_16_PRINTED_TOTALS",
    "Image",
    "ImagePlan",
    "apt_package",
    "check_plan_inputs",
    "dependency_sets",
    "image_name",
    "plan_from_graph",
    "plan_images",
    "reduction",
]

#: Table 4.16 (GB): image -> (size, optimized); parents have no standalone size. Reference data.
TABLE_4_16 = {
    "mission-rb": (4.087, 0.367),
    "hmi-webserver-rb": (0.699, 0.567),
    "arm-rb": (4.343, 0.623),
    "rostful-rb": (3.777, 0.129),
    "local-control-rb": (3.967, 0.320),
    "rms-rb": (3.769, 0.134),
    "perception-rb": (3.770, 0.135),
    "map-nav-rb": (3.886, 0.251),
    "navigation-rb": (3.771, 0.135),
    "main-rb": (4.136, 0.416),
    "hmi-rb": (3.872, 0.237),
    "wsg50-ros-pkgs": (None, 0.379),
    "summit-xl-bringup": (None, 0.052),
    "summit-xl-robot-local-control": (None, 0.000),
    "summit-xl-navigation": (None, 0.000),
    "base": (None, 3.634),
}
TABLE_4_16_PRINTED_TOTALS = (39.897, 6.705)
DEFAULT_PLATFORMS = ("amd64", "arm64")


def reduction(before: float, after: float) -> float:
    """Share of disk saved, ``1 - after / before``."""
    if before <= 0:
        raise InputError("the size before optimisation must be positive")
    return 1.0 - after / before


@dataclass(frozen=True)
class Image:
    name: str
    #: "base", "parent" or "container".
    kind: str
    #: Packages installed in this image's own layer (its Venn region).
    packages: tuple[str, ...]
    #: Containers whose dependency sets share this region (for a container image: itself).
    owners: tuple[str, ...]
    #: The image this one is ``FROM`` (``None``: the ROS distribution image).
    parent: str | None
    #: Other parent images whose region files are copied in by a multi-stage build.
    copies: tuple[str, ...]
    #: Every region image this image's content includes (FROM chain and copies).
    needs: tuple[str, ...]
    platforms: tuple[str, ...]
    own_mib: float
    copied_mib: float
    #: Full image size: distro + everything inside.
    size_mib: float
    ros_nodes: tuple[str, ...] = ()

    @property
    def unique_mib(self) -> float:
        """Bytes only this image adds on a device that holds all images (Table 4.16's "optimized")."""
        return self.own_mib + self.copied_mib

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "kind": self.kind,
            "packages": list(self.packages),
            "owners": list(self.owners),
            "parent": self.parent,
            "copies": list(self.copies),
            "needs": list(self.needs),
            "platforms": list(self.platforms),
            "own_mib": self.own_mib,
            "copied_mib": self.copied_mib,
            "unique_mib": self.unique_mib,
            "size_mib": self.size_mib,
            "ros_nodes": list(self.ros_nodes),
        }


@dataclass
class ImagePlan:
    images: list[Image]
    dockerfiles: dict[str, str]
    distro_image: str
    distro_mib: float
    before_mib: float
    after_mib: float
    repository: str = "continuum"
    tag: str = "latest"
    unknown_sizes: list[str] = field(default_factory=list)

    @property
    def saved(self) -> float:
        return reduction(self.before_mib, self.after_mib) if self.before_mib > 0 else 0.0

    def image(self, name: str) -> Image:
        for im in self.images:
            if im.name == name:
                return im
        raise KeyError(name)

    def container_images(self) -> dict[str, Image]:
        """Container name -> its image."""
        return {im.owners[0]: im for im in self.images if im.kind == "container"}

    def reference(self, name: str) -> str:
        return f"{self.repository}/{name}:{self.tag}" if self.repository else f"{name}:{self.tag}"

    def build_script(self) -> str:
        """A POSIX shell script building and pushing every image, parents first. Every value is quoted
        (``shlex.quote``), whatever it holds: the plan's inputs are checked, this is the second line."""
        lines = [
            "#!/bin/sh",
            "# Build order matters: parents are pushed before the images built FROM them.",
            "set -eu",
        ]
        for im in self.images:
            platforms = ",".join(f"linux/{p}" for p in im.platforms)
            args = ["docker", "buildx", "build", "--platform", platforms, "-t", self.reference(im.name), "--push",
                    im.name]  # fmt: skip
            lines.append(" ".join(shlex.quote(a) for a in args))
        return "\n".join(lines) + "\n"

    def to_dict(self) -> dict[str, Any]:
        return {
            "distro_image": self.distro_image,
            "distro_mib": self.distro_mib,
            "images": [im.to_dict() for im in self.images],
            "before_mib": self.before_mib,
            "after_mib": self.after_mib,
            "saved": self.saved,
            "unknown_sizes": list(self.unknown_sizes),
        }

    def archive(self, fmt: str = "tar") -> bytes:
        """The Dockerfiles (``<image>/Dockerfile``), ``build.sh`` and ``plan.json`` as a tar or zip archive,
        built in memory with fixed timestamps so the same plan gives the same bytes."""
        files = {f"{name}/Dockerfile": text for name, text in self.dockerfiles.items()}
        files["build.sh"] = self.build_script()
        files["plan.json"] = json.dumps(self.to_dict(), indent=2) + "\n"
        buf = io.BytesIO()
        if fmt == "tar":
            with tarfile.open(fileobj=buf, mode="w", format=tarfile.PAX_FORMAT) as tar:
                for path in sorted(files):
                    data = files[path].encode()
                    tar_info = tarfile.TarInfo(path)
                    tar_info.size, tar_info.mtime = len(data), 0
                    tar_info.mode = 0o755 if path.endswith(".sh") else 0o644
                    tar.addfile(tar_info, io.BytesIO(data))
        elif fmt == "zip":
            with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
                for path in sorted(files):
                    zip_info = zipfile.ZipInfo(path, date_time=(1980, 1, 1, 0, 0, 0))
                    zip_info.external_attr = (0o755 if path.endswith(".sh") else 0o644) << 16
                    zf.writestr(zip_info, files[path])
        else:
            raise InputError(f"unknown archive format {fmt!r} (tar or zip)", "format")
        return buf.getvalue()


# ---- inputs -----------------------------------------------------------------------------------------
def dependency_sets(graph: RosGraph, containers: Mapping[str, Sequence[str]]) -> dict[str, list[str]]:
    """Container -> the union of its ROS nodes' packages (in first-seen order)."""
    out: dict[str, list[str]] = {}
    for name, members in containers.items():
        deps: dict[str, None] = {}
        for m in members:
            if m not in graph.nodes:
                raise InputError(f"container {name!r} names unknown ROS node {m!r}", "containers")
            deps.update(dict.fromkeys(graph.nodes[m].packages))
        out[name] = list(deps)
    return out


def image_name(raw: str) -> str:
    """A valid image repository name component: lower case, ``[a-z0-9]`` separated by ``.``, ``_``, ``-``."""
    name = re.sub(r"[^a-z0-9._-]+", "-", raw.lower()).strip("._-")
    name = re.sub(r"[._-]{2,}", "-", name)
    return name or "image"


def apt_package(package: str, ros_distro: str, override: str | None = None) -> str:
    """The Debian package that provides ``package``: ROS packages (``nav2_core``) become
    ``ros-<distro>-nav2-core``; names that already look like Debian packages (with a dash, or ``lib*``,
    ``python3-*``) stay as they are. ``override`` (the package's ``apt`` field) wins."""
    if override:
        return override
    if "-" in package or package.startswith(("lib", "python3")):
        return package
    return f"ros-{ros_distro}-{package.replace('_', '-').lower()}"


# ---- the planner ------------------------------------------------------------------------------------
def plan_images(
    deps: Mapping[str, Sequence[str]],
    sizes_mib: Mapping[str, float] | None = None,
    *,
    archs: Mapping[str, Sequence[str]] | None = None,
    apt_names: Mapping[str, str] | None = None,
    ros_nodes: Mapping[str, Sequence[str]] | None = None,
    distro_image: str = "ros:humble-ros-base",
    ros_distro: str = "humble",
    distro_mib: float = 0.0,
    platforms: Sequence[str] = DEFAULT_PLATFORMS,
    repository: str = "continuum",
    tag: str = "latest",
) -> ImagePlan:
    """Plan base, parent and container images for containers with dependency sets ``deps``.

    ``sizes_mib`` gives package sizes (unknown ones count 0 and are listed in ``unknown_sizes``); ``archs``
    restricts a package to some architectures, so an image is built for the ``platforms`` every package in
    it supports.
    """
    if not deps:
        raise InputError("no containers to build images for", "containers")
    check_plan_inputs(deps, apt_names or {}, distro_image, ros_distro, repository, tag)
    sizes = dict(sizes_mib or {})
    for p, mib in sizes.items():
        if not (isinstance(mib, (int, float)) and mib >= 0):
            raise InputError(f"package {p!r} has invalid size {mib!r}", "packages")
    wanted_platforms = tuple(dict.fromkeys(normalize_arch(p) for p in platforms))
    pkg_archs = {p: {normalize_arch(a, f"package {p!r}") for a in a_list} for p, a_list in (archs or {}).items()}
    containers = list(deps)
    k = len(containers)

    owners: dict[str, set[str]] = {}
    for c in containers:
        for p in deps[c]:
            owners.setdefault(p, set()).add(c)
    regions: dict[frozenset[str], list[str]] = {}
    for p in sorted(owners, key=natural_key):
        regions.setdefault(frozenset(owners[p]), []).append(p)

    def size(pkgs: Iterable[str]) -> float:
        return sum(sizes.get(p, 0.0) for p in pkgs)

    # Region images, supersets first (they are the parents of the smaller overlaps).
    shared = sorted(
        (s for s in regions if len(s) >= 2),
        key=lambda s: (-len(s), -size(regions[s]), natural_key(",".join(sorted(s, key=natural_key)))),
    )
    taken: set[str] = set()
    region_name: dict[frozenset[str], str] = {}
    container_name = {c: _unique(image_name(c), taken) for c in containers}
    for s in shared:
        if len(s) == k:
            region_name[s] = _unique("base", taken)
        else:
            largest = min(regions[s], key=lambda p: (-sizes.get(p, 0.0), natural_key(p)))
            region_name[s] = _unique(image_name(largest.replace("_", "-")), taken)

    content: dict[str, set[str]] = {}  # image -> region images it holds (itself included for regions)
    region_bytes = {region_name[s]: size(regions[s]) for s in shared}
    images: list[Image] = []
    dockerfiles: dict[str, str] = {}

    def choose(needs: set[str]) -> tuple[str | None, list[str]]:
        """FROM the needed image holding the most bytes; copy the needed regions it lacks."""
        if not needs:
            return None, []
        parent = min(needs, key=lambda r: (-sum(region_bytes[x] for x in content[r]), -len(content[r]), natural_key(r)))
        copies = sorted(needs - content[parent], key=lambda r: (-region_bytes[r], natural_key(r)))
        return parent, copies

    def image_platforms(pkgs: Iterable[str], needs: Iterable[str]) -> tuple[str, ...]:
        allowed = set(wanted_platforms)
        for p in pkgs:
            if p in pkg_archs:
                allowed &= pkg_archs[p]
        for r in needs:
            allowed &= set(next(im.platforms for im in images if im.name == r))
        return tuple(a for a in wanted_platforms if a in allowed)

    for s in shared:
        name = region_name[s]
        needs = {region_name[t] for t in shared if t > s}
        parent, copies = choose(needs)
        content[name] = {name} | needs
        pkgs = tuple(regions[s])
        plats = image_platforms(pkgs, needs)
        copied = sum(region_bytes[r] for r in copies)
        im = Image(
            name=name,
            kind="base" if len(s) == k else "parent",
            packages=pkgs,
            owners=tuple(sorted(s, key=natural_key)),
            parent=parent,
            copies=tuple(copies),
            needs=tuple(sorted(needs, key=natural_key)),
            platforms=plats,
            own_mib=region_bytes[name],
            copied_mib=copied,
            size_mib=distro_mib + sum(region_bytes[r] for r in content[name]),
        )
        images.append(im)
    for c in containers:
        name = container_name[c]
        needs = {region_name[s] for s in shared if c in s}
        parent, copies = choose(needs)
        own = tuple(regions.get(frozenset({c}), ()))
        plats = image_platforms(own, needs)
        im = Image(
            name=name,
            kind="container",
            packages=own,
            owners=(c,),
            parent=parent,
            copies=tuple(copies),
            needs=tuple(sorted(needs, key=natural_key)),
            platforms=plats,
            own_mib=size(own),
            copied_mib=sum(region_bytes[r] for r in copies),
            size_mib=distro_mib + size(deps[c]),
            ros_nodes=tuple((ros_nodes or {}).get(c, ())),
        )
        images.append(im)
    for im in images:
        dockerfiles[im.name] = _dockerfile(im, distro_image, ros_distro, apt_names or {}, repository, tag)

    before = sum(distro_mib + size(deps[c]) for c in containers)
    after = distro_mib + sum(size(pkgs) for pkgs in regions.values()) + sum(im.copied_mib for im in images)
    unknown = sorted((p for p in owners if p not in sizes), key=natural_key)
    return ImagePlan(images, dockerfiles, distro_image, distro_mib, before, after, repository, tag, unknown)


def check_plan_inputs(
    deps: Mapping[str, Sequence[str]],
    apt_names: Mapping[str, str],
    distro_image: str,
    ros_distro: str,
    repository: str,
    tag: str,
) -> None:
    """Every value that reaches ``build.sh`` or a Dockerfile must follow its grammar (see
    :mod:`.artifact_names`); InputError naming the field otherwise."""
    if repository:
        artifact_names.check_repository(repository)
    artifact_names.check_tag(tag)
    artifact_names.check_reference(distro_image, "distro_image", "distro_image")
    artifact_names.check_ros_distro(ros_distro, "ros_distro")
    for container, packages in deps.items():
        for p in packages:
            artifact_names.check_package(p, "packages", f"container {container!r}: package")
    for p, apt in apt_names.items():
        artifact_names.check_package(apt, "packages", f"package {p!r}: apt name")


def plan_from_graph(graph: RosGraph, containers: Mapping[str, Sequence[str]], **params: Any) -> ImagePlan:
    """:func:`plan_images` for containers of ROS nodes, with sizes/archs/apt names from ``graph.packages``."""
    deps = dependency_sets(graph, containers)
    info = graph.packages
    params.setdefault("sizes_mib", {p: v.get("size_mib", 0.0) for p, v in info.items()})
    params.setdefault("archs", {p: v["archs"] for p, v in info.items() if "archs" in v})
    params.setdefault("apt_names", {p: v["apt"] for p, v in info.items() if v.get("apt")})
    params.setdefault("ros_nodes", {c: list(ms) for c, ms in containers.items()})
    sizes = params.pop("sizes_mib")
    return plan_images(deps, sizes, **params)


def _unique(name: str, taken: set[str]) -> str:
    candidate, i = name, 2
    while candidate in taken:
        candidate, i = f"{name}-{i}", i + 1
    taken.add(candidate)
    return candidate


def _dockerfile(
    im: Image, distro_image: str, ros_distro: str, apt_names: Mapping[str, str], repository: str, tag: str
) -> str:
    def ref(name: str) -> str:
        return f"{repository}/{name}:{tag}" if repository else f"{name}:{tag}"

    what = {
        "base": "packages every container needs",
        "parent": f"packages shared by {', '.join(im.owners)}",
        "container": f"container {im.owners[0]}",
    }[im.kind]
    lines = [
        "# syntax=docker/dockerfile:1.4",
        f"# Generated by Continuum (thesis 3.2.1, Fig. 3.24): {_one_line(what)}.",
        f"# Platforms: {', '.join('linux/' + p for p in im.platforms) or 'none (a package exists on no target)'}",
    ]
    for c in im.copies:
        lines.append(f"FROM {ref(c)} AS stage-{c}")
    lines.append(f"FROM {ref(im.parent) if im.parent else distro_image}")
    lines.append(
        f"LABEL io.continuum.image.kind={_docker_string(im.kind)} "
        f"io.continuum.image.owners={_docker_string(','.join(im.owners))}"
    )
    for c in im.copies:
        # Copy exactly the files the parent's packages installed (its dpkg manifest); the dpkg database
        # itself is not merged, so apt in this image does not know about them.
        lines.append(
            f"RUN --mount=type=bind,from=stage-{c},source=/,target=/mnt/{c} \\\n"
            f"    sed 's|^/||' /mnt/{c}/opt/continuum/{c}.files \\\n"
            f"    | tar -C /mnt/{c} --no-recursion --ignore-failed-read -cf - -T - | tar -C / -xpf - \\\n"
            f"    && mkdir -p /opt/continuum && cp /mnt/{c}/opt/continuum/{c}.files /opt/continuum/"
        )
    if im.packages:
        apt = " ".join(shlex.quote(apt_package(p, ros_distro, apt_names.get(p))) for p in im.packages)
        install = (
            "apt-get update \\\n"
            f"    && apt-get install -y --no-install-recommends {apt} \\\n"
            "    && rm -rf /var/lib/apt/lists/*"
        )
        if im.kind == "container":
            lines.append(f"RUN {install}")
        else:
            # Record what this layer installed so that children can copy it in a multi-stage build.
            lines.append(
                "RUN dpkg-query -W -f='${Package}\\n' | sort > /tmp/continuum-before \\\n"
                f"    && {install} \\\n"
                "    && mkdir -p /opt/continuum \\\n"
                "    && dpkg-query -W -f='${Package}\\n' | sort | comm -13 /tmp/continuum-before - \\\n"
                "       | xargs -r dpkg -L | grep '^/' | grep -vxF '/.' \\\n"
                f"       | sort -u > /opt/continuum/{im.name}.files \\\n"
                "    && rm /tmp/continuum-before"
            )
    elif im.kind != "container":
        lines.append(f"RUN mkdir -p /opt/continuum && : > /opt/continuum/{im.name}.files")
    if im.ros_nodes:
        lines.append(f"ENV CONTINUUM_ROS_NODES={_docker_string(' '.join(im.ros_nodes))}")
    return "\n".join(lines) + "\n"


def _one_line(text: str) -> str:
    """Text for a Dockerfile comment: a line break would end the comment and start an instruction."""
    return "".join(ch if ch.isprintable() else "?" for ch in text)


def _docker_string(value: str) -> str:
    """A double-quoted Dockerfile word (LABEL, ENV): BuildKit's lexer takes ``\\"``, ``\\$`` and ``\\\\`` as
    escapes inside double quotes, and every other character literally; line breaks are replaced, as a
    Dockerfile instruction cannot hold one."""
    escaped = re.sub(r'(["$\\])', r"\\\1", _one_line(value))
    return f'"{escaped}"'
