from typing import Literal

ClusteringsDockerfilesRetrieveArchive = Literal["tar.gz", "zip"]

CLUSTERINGS_DOCKERFILES_RETRIEVE_ARCHIVE_VALUES: set[ClusteringsDockerfilesRetrieveArchive] = {
    "tar.gz",
    "zip",
}


def check_clusterings_dockerfiles_retrieve_archive(value: str) -> ClusteringsDockerfilesRetrieveArchive:
    if value in CLUSTERINGS_DOCKERFILES_RETRIEVE_ARCHIVE_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {CLUSTERINGS_DOCKERFILES_RETRIEVE_ARCHIVE_VALUES!r}")
