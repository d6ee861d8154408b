"""The rig a MOP character's config entry draws with (:mod:`tabletop.plugins.mop` builds the
characters with it): a sprite sheet, the creature, the face, the hybrid of both, or a projected
humanoid skeleton (a URDF, pybullet_data's humanoid by default)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Callable, Union

from behaviors.mop.puppetry import FaceRig, HumanoidRig, HybridRig, PlanarRig
from tabletop.files import MAX_CLIP_BYTES, UnreadableText, json_loads, read_text_within
from tabletop.plugins.mop_files import MopError

#: The creature's point its face rides on in a hybrid character (its nose).
HYBRID_HEAD = 3
#: A hybrid humanoid's face stands on its neck, up toward its crown (points of the projected
#: pybullet_data humanoid), and is this tall (x its standing height): the head's own 0.17 (neck
#: to crown) makes the example's 0.26 m mime a 38 px face on the 1280 x 720 view of the 1.2 m
#: table (840 px/m), its eyes 3 px tall; 0.3 draws it 68 px tall (its jaw open), eyes 5 px.
HUMANOID_NECK, HUMANOID_HEAD, HUMANOID_FACE = 5, 16, 0.3

Rig = Union[PlanarRig, FaceRig, HybridRig, HumanoidRig]


def make_rig(c: dict) -> Rig:
    """The rig of MOP character entry ``c`` (its ``kind``); a sprite sheet that cannot be read
    is a MopError naming the file."""
    if c["kind"] == "sprite":
        from behaviors.mop.sprites import sprite_sheet_from_mapping
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
    if c["kind"] == "hybrid" and c.get("body") == "humanoid":
        from behaviors.mop.creatures import FaceModel
        return HybridRig(_humanoid(c), FaceRig(FaceModel()), HUMANOID_HEAD, HUMANOID_FACE,
                         neck=HUMANOID_NECK)
    if c["kind"] == "hybrid":
        from behaviors.mop.creatures import FaceModel, creature_skeleton
        return HybridRig(PlanarRig(creature_skeleton()), FaceRig(FaceModel()), HYBRID_HEAD)
    return _humanoid(c)


def motion_kind(c: dict) -> str:
    """The kind whose motions character entry ``c`` plays (its built-in clips): its ``kind``,
    or ``humanoid_hybrid`` for a hybrid whose body is a humanoid."""
    humanoid = c["kind"] == "hybrid" and c.get("body") == "humanoid"
    return "humanoid_hybrid" if humanoid else c["kind"]


def check_body(c: dict, defaults: dict, where: str, error: Callable[[str, str], Exception]
               ) -> None:
    """Refuse, naming its key (``error(path, message)``), what character entry ``c`` (at
    ``where``) gives other than its ``defaults`` that its body does not read: ``body`` but on a
    hybrid; a hybrid humanoid's own URDF (its face stands on pybullet_data's humanoid's neck);
    a humanoid's view for a hybrid whose body is a creature (seen from above)."""
    hybrid = c["kind"] == "hybrid"
    for key in ("body", "skeleton", "view_yaw", "elevation", "travel") if hybrid else ("body",):
        if c[key] == defaults[key]:
            continue
        if key == "body":
            if not hybrid:
                raise error(f"{where}.body", f"only a hybrid character takes body; a "
                                             f"{c['kind']} character does not read it")
        elif key == "skeleton":
            raise error(f"{where}.skeleton", "a hybrid's humanoid is pybullet_data's (its face "
                                             "stands on that figure's neck): it takes no skeleton")
        elif c["body"] != "humanoid":
            raise error(f"{where}.{key}", f"a hybrid reads {key} only with body: humanoid (a "
                                          "creature's body is seen from above)")


def _humanoid(c: dict) -> HumanoidRig:
    """The projected humanoid of a skeleton character (or a hybrid's humanoid body)."""
    from behaviors.motion.deepmimic import ROOT_SCALE, humanoid_urdf
    from behaviors.motion.skeleton import ProjectedFigure, Projection, load_urdf
    urdf = c["skeleton"] or humanoid_urdf()
    return HumanoidRig(ProjectedFigure(load_urdf(urdf), Projection(
        view_yaw=c["view_yaw"], elevation=c["elevation"]), root_scale=ROOT_SCALE),
        travel=c["travel"])
