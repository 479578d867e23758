"""Table 4.16 from images: an RB-Kairos-like image plan (Fig. 3.24) built for real with buildah, measured.

    sudo python benchmarks/image_inheritance_build.py [--json FILE]

Six ROS 1 containers of an RB-Kairos-like robot, each needing Debian's ROS packages (``python3-rospy``,
``ros-core``, message packages). The planner (continuum.engine.containers.image_inheritance) puts the shared
packages in parent images; apps.containers.imagebuild builds base -> parents -> children with buildah from
``continuum/base:bookworm`` (scripts/build-images.sh base: debootstrap minbase), reads every layer's size from
buildah's storage, and prints the measured disk before (each container image alone) and after (all on one
device) next to the planner's prediction (apt's Installed-Size of each package with the dependencies the base
lacks) and the thesis' 83.2 %. Needs root and buildah; a few minutes (apt downloads from Debian's mirror).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _bench import loadavg, table  # noqa: E402

from apps.containers import imagebuild  # noqa: E402

MSGS = ["python3-std-msgs", "python3-geometry-msgs"]
#: RB-Kairos-like containers (thesis Table 4.16 names) with Debian's ROS 1 packages.
CONTAINERS = {
    "master-rb": ["ros-core", "python3-rospy"],
    "mission-rb": ["python3-rospy", *MSGS, "python3-actionlib"],
    "navigation-rb": ["python3-rospy", *MSGS, "python3-nav-msgs", "python3-tf2-ros"],
    "local-control-rb": ["python3-rospy", *MSGS, "python3-nav-msgs"],
    "perception-rb": ["python3-rospy", *MSGS, "python3-sensor-msgs"],
    "hmi-rb": ["python3-rospy", "python3-std-msgs", "python3-sensor-msgs"],
}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", type=Path, help="write the measurements here")
    args = ap.parse_args()
    plan, base_mib = imagebuild.predict(CONTAINERS)
    print(f"base {imagebuild.BASE_IMAGE}: {base_mib:.1f} MiB; {len(plan.images)} images planned; load {loadavg()}")
    built = imagebuild.build(plan, lambda pct, msg: print(f"  [{pct:3d}%] {msg}", flush=True))
    rows = [[im["name"], im["kind"], im["parent"].split("/")[-1], len(im["layers"]), f"{im['own_mib']:.1f}",
             f"{im['predicted_own_mib']:.1f}", f"{im['size_mib']:.1f}", f"{im['predicted_size_mib']:.1f}",
             f"{im['build_s']:.0f}"] for im in built["images"]]  # fmt: skip
    print(table(["image", "kind", "FROM", "layers", "own MiB", "pred.", "size MiB", "pred.", "build s"], rows))
    print(f"disk before {built['before_mib']:.1f} MiB (predicted {built['predicted_before_mib']:.1f}), after "
          f"{built['after_mib']:.1f} MiB (predicted {built['predicted_after_mib']:.1f})")  # fmt: skip
    print(f"saving: measured {built['saved'] * 100:.1f} %, planner's prediction {built['predicted_saved'] * 100:.1f} %,"
          f" thesis (Table 4.16) {built['thesis_saved'] * 100:.1f} %; load {loadavg()}")  # fmt: skip
    if args.json:
        args.json.write_text(json.dumps(built, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
