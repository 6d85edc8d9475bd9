"""The conditions a panel's data was computed under, and whether they are the walk's.

A drift surface or a finder's result describes one ground, body mass and slope; drawn beside a
walk under other conditions it misleads (the live point sits on a map that is not its own). So
every panel names its conditions in its title and draws only data of the walk's own: the
ground, and the mass and slope at the same position of their sliders (`Conditions.key`: values
rounded to the slider's step, so 5.96 g and 6.04 g are one condition and 6.0 g and 6.1 g two,
exactly as a person can tell them apart).

Where the typed records carry their conditions: a `DriftSurface` names its ground, mass and
slope, and the model's leaves off their defaults (`params`: a surface of other model
parameters is not the walk's map either, `same_model`); a `FinderOutput` names mass and slope
per cell, but not its ground: the results folder's bifurcation file is written by the core's
default model (`insect-gait reproduce`, and `insect-gait finder` without model flags: with
them it writes a file of another name that names its ground and leaves), so a file
that names no ground was walked on `GROUND_DEFAULT`. A `SurfaceAtlas`
names its ground, not the value it holds the other axis at: `insect-gait atlas` holds it at
`RunSpec`'s default (3 g, level) unless told otherwise, and then names its file otherwise.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from sim_core.contract import GROUND_DEFAULT, DriftSurface, FinderOutput, ModelChoice, RunSpec
from web import controls
from web.record import D31Event

MASS_STEP = controls.BODY_MASS_G.step  # g: what the mass slider tells apart
SLOPE_STEP = controls.SLOPE_DEG.step  # deg


@dataclass(frozen=True)
class Conditions:
    """What a walk, a surface or a finder cell ran under besides beta and its start."""

    ground: str  # `ModelParams.ground`
    body_mass_g: float
    slope_deg: float

    @property
    def key(self) -> tuple[str, int, int]:
        """The same key: the same ground and the same slider positions of mass and slope."""
        return (
            self.ground,
            round(self.body_mass_g / MASS_STEP),
            round(self.slope_deg / SLOPE_STEP),
        )

    def matches(self, other: Conditions) -> bool:
        return self.key == other.key

    def snapped(self) -> Conditions:
        """The mass and slope on their sliders' grid (what a job for these conditions asks)."""
        _, m, s = self.key
        return Conditions(self.ground, round(m * MASS_STEP, 6), round(s * SLOPE_STEP, 6) + 0.0)

    def label(self) -> str:
        """How titles and notes name the conditions: "penalty ground, 6.0 g, slope 0°"."""
        c = self.snapped()
        return f"{ground_words(self.ground)}, {c.body_mass_g:.1f} g, slope {c.slope_deg:g}°"


def ground_words(ground: str) -> str:
    """The ground by its button's name, said to be a ground ("penalty ground")."""
    labels: dict[str, str] = {str(g): str(name) for g, name in controls.GROUND_LABEL.items()}
    name = labels.get(ground, ground)
    return name if "ground" in name else f"{name} ground"


def of_surface(s: DriftSurface) -> Conditions:
    return Conditions(s.ground, s.body_mass_g, s.slope_deg)


def model_of(want: Conditions, model: ModelChoice | None) -> ModelChoice:
    """The model parameters asked with `want` (None: the defaults on its ground)."""
    return model if model is not None else ModelChoice(ground=want.ground)


def same_model(s: DriftSurface, model: ModelChoice) -> bool:
    """Whether a surface was computed with `model`'s leaves (what it records, `params`; the
    ground is its conditions'): a surface of other parameters is not the walk's map."""
    return s.params == model.changed()


def of_event(e: D31Event) -> Conditions:
    return Conditions(e.at.ground, e.at.body_mass_g, e.at.slope_deg)


def finder_ground(out: FinderOutput) -> str:
    """The ground a finder's output was walked on (module docstring: the default unless it
    names one)."""
    return out.ground or GROUND_DEFAULT


def finder_conditions(out: FinderOutput) -> list[Conditions]:
    """The distinct conditions of a finder's cells, in the order they first appear."""
    ground = finder_ground(out)
    seen: dict[tuple[str, int, int], Conditions] = {}
    for c in out.cells:
        cond = Conditions(ground, c.body_mass_g, c.slope_deg)
        seen.setdefault(cond.key, cond)
    return list(seen.values())


def finder_for(out: FinderOutput, want: Conditions) -> FinderOutput | None:
    """The finder's cells of `want`'s conditions (None: it has none)."""
    ground = finder_ground(out)
    cells = [c for c in out.cells if Conditions(ground, c.body_mass_g, c.slope_deg).matches(want)]
    return out.model_copy(update={"cells": cells}) if cells else None


def events_of(events: Sequence[D31Event], want: Conditions) -> list[D31Event]:
    """The walk's events taken under `want` (a trail at another mass is not this diagram's)."""
    return [e for e in events if of_event(e).matches(want)]


def atlas_conditions(ground: str) -> Conditions:
    """What an atlas on `ground` holds fixed (module docstring): RunSpec's default mass and
    slope; `atlas_holds` compares only the one its axis does not sweep."""
    fields = RunSpec.model_fields
    return Conditions(
        ground, float(fields["body_mass_g"].default), float(fields["slope_deg"].default)
    )


def atlas_holds(axis: str, atlas: Conditions, walk: Conditions) -> bool:
    """Whether the walk is on the atlas's ground and at the value the atlas holds fixed (its
    slope for an atlas over mass, its mass for one over slope)."""
    if axis == "mass":
        return Conditions(walk.ground, atlas.body_mass_g, walk.slope_deg).matches(atlas)
    return Conditions(walk.ground, walk.body_mass_g, atlas.slope_deg).matches(atlas)


def atlas_label(axis: str, atlas: Conditions) -> str:
    """The ground and the held parameter: "penalty ground, slope 0°" (an atlas over mass) or
    "constraint ground, 3.0 g" (over slope)."""
    c = atlas.snapped()
    held = f"slope {c.slope_deg:g}°" if axis == "mass" else f"{c.body_mass_g:.1f} g"
    return f"{ground_words(atlas.ground)}, {held}"
