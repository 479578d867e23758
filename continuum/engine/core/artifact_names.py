"""Grammars of the names that end up in generated build artifacts (``build.sh``, Dockerfiles, pod specs).

These values come from users (image options, ROS graph documents) and are written into files that a shell
and ``docker build`` execute, so they are checked against the grammar of what they name before anything is
generated: image references by the OCI distribution reference grammar (``distribution/reference``), package
names by Debian policy 5.6.1 (``[a-z0-9][a-z0-9+.-]+``) or ROS REP 144 (``[a-z][a-z0-9_]*``). The
generators still quote what they write (defence in depth); the checks make sure nothing odd gets that far.
Each ``*_problem`` function returns ``None`` for a valid name, else a short reason; ``check_*`` raise
:class:`~continuum.engine.core.errors.InputError` naming the field.
"""

from __future__ import annotations

import re

from continuum.engine.core.errors import InputError

__all__ = [
    "DEBIAN_PACKAGE_RE",
    "NAME_MAX",
    "NAME_RE",
    "REFERENCE_RE",
    "ROS_DISTRO_RE",
    "ROS_PACKAGE_RE",
    "TAG_RE",
    "check_package",
    "check_reference",
    "check_repository",
    "check_ros_distro",
    "check_tag",
    "package_problem",
    "reference_problem",
    "repository_problem",
    "ros_distro_problem",
    "tag_problem",
]

# distribution/reference grammar (reference.go):
#   reference  := name [ ":" tag ] [ "@" digest ]
#   name       := [domain '/'] path-component ['/' path-component]*
#   domain     := host [':' port-number]
_ALNUM = r"[a-z0-9]+"
_SEPARATOR = r"(?:[._]|__|[-]+)"
_PATH_COMPONENT = rf"{_ALNUM}(?:{_SEPARATOR}{_ALNUM})*"
_DOMAIN_COMPONENT = r"(?:[a-zA-Z0-9]|[a-zA-Z0-9][a-zA-Z0-9-]*[a-zA-Z0-9])"
_HOST = rf"(?:{_DOMAIN_COMPONENT}(?:\.{_DOMAIN_COMPONENT})*|\[[0-9a-fA-F:]+\])"
_DOMAIN = rf"{_HOST}(?::[0-9]+)?"
_NAME = rf"(?:{_DOMAIN}/)?{_PATH_COMPONENT}(?:/{_PATH_COMPONENT})*"
_TAG = r"[\w][\w.-]{0,127}"
_DIGEST = r"[A-Za-z][A-Za-z0-9]*(?:[-_+.][A-Za-z][A-Za-z0-9]*)*:[0-9a-fA-F]{32,}"

NAME_RE = re.compile(_NAME, re.ASCII)
TAG_RE = re.compile(_TAG, re.ASCII)
REFERENCE_RE = re.compile(rf"(?P<name>{_NAME})(?::(?P<tag>{_TAG}))?(?:@(?P<digest>{_DIGEST}))?", re.ASCII)
#: Longest repository name the registry accepts (``reference.NameTotalLengthMax``).
NAME_MAX = 255
DEBIAN_PACKAGE_RE = re.compile(r"[a-z0-9][a-z0-9+.-]+", re.ASCII)
ROS_PACKAGE_RE = re.compile(r"[a-z][a-z0-9_]*", re.ASCII)
#: ROS distribution names (humble, jazzy, rolling...): they become part of Debian package names.
ROS_DISTRO_RE = re.compile(r"[a-z][a-z0-9]*", re.ASCII)


def _text(value: object) -> str | None:
    return value if isinstance(value, str) else None


def repository_problem(value: object) -> str | None:
    """An image repository (a reference's name, without tag or digest): ``[host[:port]/]path``."""
    text = _text(value)
    if text is None:
        return "must be a string"
    if len(text) > NAME_MAX:
        return f"longer than {NAME_MAX} characters"
    if not NAME_RE.fullmatch(text):
        return (
            f"{text!r} is not an image repository ([registry[:port]/]path, path components of lowercase "
            "letters and digits separated by '.', '_', '__' or '-')"
        )
    return None


def tag_problem(value: object) -> str | None:
    text = _text(value)
    if text is None:
        return "must be a string"
    if not TAG_RE.fullmatch(text):
        return f"{text!r} is not an image tag (a letter, digit or '_', then up to 127 of those, '.' or '-')"
    return None


def reference_problem(value: object) -> str | None:
    """A full image reference: ``[registry[:port]/]path[:tag][@digest]``."""
    text = _text(value)
    if text is None:
        return "must be a string"
    match = REFERENCE_RE.fullmatch(text)
    if match is None:
        return f"{text!r} is not an image reference ([registry[:port]/]path[:tag][@digest], lowercase path)"
    if len(match["name"]) > NAME_MAX:
        return f"the repository name is longer than {NAME_MAX} characters"
    return None


def package_problem(value: object) -> str | None:
    """A Debian package name or a ROS package name."""
    text = _text(value)
    if text is None:
        return "must be a string"
    if DEBIAN_PACKAGE_RE.fullmatch(text) or ROS_PACKAGE_RE.fullmatch(text):
        return None
    return f"{text!r} is not a package name (Debian: [a-z0-9][a-z0-9+.-]+, ROS: [a-z][a-z0-9_]*)"


def ros_distro_problem(value: object) -> str | None:
    text = _text(value)
    if text is None:
        return "must be a string"
    if not ROS_DISTRO_RE.fullmatch(text) or len(text) > 40:
        return f"{text!r} is not a ROS distribution name (lowercase letters and digits, e.g. humble)"
    return None


def _check(problem: str | None, field: str, what: str) -> None:
    if problem is not None:
        raise InputError(f"{what}: {problem}", field)


def check_repository(value: object, field: str = "repository", what: str = "repository") -> None:
    _check(repository_problem(value), field, what)


def check_tag(value: object, field: str = "tag", what: str = "tag") -> None:
    _check(tag_problem(value), field, what)


def check_reference(value: object, field: str = "image", what: str = "image") -> None:
    _check(reference_problem(value), field, what)


def check_package(value: object, field: str = "packages", where: str = "package") -> None:
    _check(package_problem(value), field, where)


def check_ros_distro(value: object, field: str = "ros_distro", what: str = "ros_distro") -> None:
    _check(ros_distro_problem(value), field, what)
