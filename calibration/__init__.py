"""calibration: camera intrinsics, camera <-> table and table <-> projector homographies."""
