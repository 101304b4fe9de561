"""A frame-mode station in the cell's page (codegen/view/): the bench under its user frame, the photo pose and the
poses taught in the frame."""

from __future__ import annotations

import numpy as np

from codegen.view.scene import SLAB_MM, box, frame, line, translated

BENCH_MARGIN_MM = 120.0  # the bench reaches this far beyond the taught poses around its mark


def objects(cell, station) -> list[dict]:
    user2base = station.spec.frame.matrix()
    poses = [user2base @ p.matrix() for p in station.path]
    photo = user2base @ station.spec.photo.matrix()
    local = np.array([np.linalg.solve(user2base, p)[:3, 3] for p in [*poses, photo]])
    low = np.minimum(local.min(axis=0)[:2], 0.0) - BENCH_MARGIN_MM
    high = np.maximum(local.max(axis=0)[:2], 0.0) + BENCH_MARGIN_MM
    centre = translated(user2base, ((low[0] + high[0]) / 2, (low[1] + high[1]) / 2, -SLAB_MM / 2))
    out = [
        box(centre, (*(high - low), SLAB_MM), "bench", f"{station.name}: bench"),
        frame(user2base, f"{station.name}: user frame (mark)", "mark", 80.0),
        frame(photo, f"{station.name}: photo", "camera"),
    ]
    out += [frame(p, f"{station.name}: {t.name}", "taught") for p, t in zip(poses, station.path, strict=True)]
    out.append(line([p[:3, 3] for p in poses], "taught", dashed=True))
    return out
