"""Recording and viewing: rosbag2-profile MCAP files (:mod:`.mcap`) and the rerun view
(:mod:`.rerun`). Imported lazily: ``mcap``, ``rosbags`` and ``rerun`` are optional extras."""

__all__: list[str] = []
