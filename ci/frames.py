"""A run folder's frames, for the scripts in ci/ (check-vtu.py, taylor-foot.py): the last frame_NNNNN.vtu."""

import os
import re
import sys


def last_frame(run):
    """The path of the run folder's last frame; exits naming the folder when it has none."""
    frames = sorted(f for f in os.listdir(run) if re.fullmatch(r"frame_\d+\.vtu", f))
    if not frames:
        sys.exit(f"{run}: no frame_*.vtu")
    return os.path.join(run, frames[-1])
