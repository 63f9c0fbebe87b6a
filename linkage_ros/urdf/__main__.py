"""``python -m linkage_ros.urdf``: the same as ``linkage-urdf``."""

from __future__ import annotations

from . import main

raise SystemExit(main())
