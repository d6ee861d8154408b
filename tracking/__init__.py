"""tracking: inputs (camera, markers, puck tracker, synthetic camera, motion capture, replay)."""
