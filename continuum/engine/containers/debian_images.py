"""An image plan (Fig. 3.24) as Containerfiles that build on this machine: Debian packages, no registry.

The plan's Dockerfiles (:mod:`.image_inheritance`) are for ``docker buildx`` from a ROS distribution image in a
registry; here none is reachable, but Debian's mirror is and Debian ships ROS 1 (``python3-rospy``,
``ros-core``, the message packages). So the base image is ``continuum/base:bookworm`` (debootstrap, built by
``scripts/build-images.sh base``), and each image is ``FROM`` its parent with one ``RUN apt-get install`` of its
region's packages: the child inherits the parent's layers, as in the plan. A region the plan copies in by a
multi-stage build (multiple inheritance) is installed again from the same packages instead (its bytes count
again in the child, as the copied bytes do in the plan). A package given as a ROS name is mapped by the plan
(``ros-<distro>-...``), which Debian does not have: give Debian names (``python3-*``, ``ros-*``, ``lib*``).
"""

from __future__ import annotations

import shlex
from dataclasses import dataclass

from continuum.engine.containers.image_inheritance import ImagePlan
from continuum.engine.core import artifact_names
from continuum.engine.core.errors import InputError

BASE_IMAGE = "continuum/base:bookworm"
#: Images built here are named under this prefix in buildah's storage (``localhost/<prefix>/<image>:<tag>``).
LOCAL_PREFIX = "continuum-built"


@dataclass(frozen=True)
class BuildStep:
    """One image to build, after its parent: the Containerfile and the Debian packages its own layer adds."""

    image: str
    kind: str
    reference: str
    parent: str  # a reference: the base image or the parent step's
    packages: tuple[str, ...]
    containerfile: str


def reference(image: str, tag: str = "latest") -> str:
    return f"{LOCAL_PREFIX}/{image}:{tag}"


def build_steps(plan: ImagePlan, base: str = BASE_IMAGE, tag: str = "latest") -> list[BuildStep]:
    """The plan's images in build order (parents first), each ``FROM`` its parent (or ``base``)."""
    artifact_names.check_reference(base, "images", "images.base")
    artifact_names.check_tag(tag, "images", "images.tag")
    regions = {im.name: im.packages for im in plan.images}
    steps: list[BuildStep] = []
    for im in plan.images:  # the plan lists parents before the images built FROM them
        packages = list(im.packages)
        for other in im.copies:
            packages += [p for p in regions[other] if p not in packages]
        for p in packages:
            if artifact_names.package_problem(p):
                raise InputError(f"package {p!r} is not a Debian package name", "packages")
        parent = reference(im.parent, tag) if im.parent else base
        lines = [f"FROM {parent}"]
        if packages:
            install = " ".join(shlex.quote(p) for p in packages)
            # One layer: the lists fetched and removed in the same RUN, so they never count in the image.
            lines.append(
                "RUN apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "
                f"--no-install-recommends {install} >/dev/null && apt-get clean && rm -rf /var/lib/apt/lists/*"
            )
        lines.append(f'LABEL continuum.image="{im.name}" continuum.kind="{im.kind}"')
        steps.append(BuildStep(im.name, im.kind, reference(im.name, tag), parent, tuple(packages),
                               "\n".join(lines) + "\n"))  # fmt: skip
    return steps
