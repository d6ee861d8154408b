"""The rig a MOP character's config entry draws with (:mod:`tabletop.plugins.mop` builds the
characters with it): a sprite sheet, the creature, the face, the hybrid of both, or a projected
humanoid skeleton (a URDF, pybullet_data's humanoid by default)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Union

from behaviors.mop.puppetry import FaceRig, HumanoidRig, HybridRig, PlanarRig
from tabletop.files import MAX_CLIP_BYTES, UnreadableText, json_loads, read_text_within
from tabletop.plugins.mop_files import MopError

#: The creature's point its face rides on in a hybrid character (its nose).
HYBRID_HEAD = 3

Rig = Union[PlanarRig, FaceRig, HybridRig, HumanoidRig]


def make_rig(c: dict) -> Rig:
    """The rig of MOP character entry ``c`` (its ``kind``); a sprite sheet that cannot be read
    is a MopError naming the file."""
    if c["kind"] == "sprite":
        from behaviors.mop.puppetry import sprite_sheet_from_mapping
        try:
            data = json_loads(read_text_within(Path(c["sheet"]), MAX_CLIP_BYTES, "sprite sheet",
                                               MopError))
        except (OSError, UnreadableText, json.JSONDecodeError) as exc:
            raise MopError(f"{c['sheet']}: cannot read sprite sheet: {exc}") from None
        return sprite_sheet_from_mapping(data, str(c["sheet"]))
    if c["kind"] == "creature":
        from behaviors.mop.creatures import creature_skeleton
        return PlanarRig(creature_skeleton())
    if c["kind"] == "face":
        from behaviors.mop.creatures import FaceModel
        return FaceRig(FaceModel())
    if c["kind"] == "hybrid":
        from behaviors.mop.creatures import FaceModel, creature_skeleton
        return HybridRig(PlanarRig(creature_skeleton()), FaceRig(FaceModel()), HYBRID_HEAD)
    from behaviors.motion.deepmimic import ROOT_SCALE, humanoid_urdf
    from behaviors.motion.skeleton import ProjectedFigure, Projection, load_urdf
    urdf = c["skeleton"] or humanoid_urdf()
    return HumanoidRig(ProjectedFigure(load_urdf(urdf), Projection(
        view_yaw=c["view_yaw"], elevation=c["elevation"]), root_scale=ROOT_SCALE),
        travel=c["travel"])
