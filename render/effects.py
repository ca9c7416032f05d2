"""Which camera effects a scene's samples get, and why (DESIGN.md, "Effects: simulate only what the scene calls
for").

``effects: auto`` switches each effect on when the scene needs it; an explicit list switches on exactly the
effects named. Effects this version cannot simulate are reported as off with that reason, and asking for one
explicitly is an input error rather than a silent no-op.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from vc.errors import InputError
from vc.scenes.loader import Scene
from vc.scenes.schema import Lighting

#: Effects this renderer does not simulate yet, with the reason shown in the plan.
NOT_SIMULATED = {
    "motion_blur": "not simulated in this version (needs the exposure time from photometric calibration)",
    "sensor_noise": "not simulated in this version (needs a noise estimate from the background)",
    "jpeg": "not simulated in this version (needs the stream's compression settings)",
    "defocus": "not simulated: surveillance cameras are focused over their whole ground range",
}


@dataclass(frozen=True)
class EffectDecision:
    name: str
    on: bool
    reason: str

    def to_dict(self) -> dict:
        return asdict(self)


def plan_effects(scene: Scene, lighting: Lighting) -> list[EffectDecision]:
    explicit = None if scene.effects == "auto" else set(scene.effects)
    for name in sorted((explicit or set()) & NOT_SIMULATED.keys()):
        raise InputError(scene.path, "effects", f"{name} is {NOT_SIMULATED[name]}")
    distorted = not scene.camera.distortion.is_identity
    if explicit is not None and "lens_distortion" not in explicit and distorted:
        raise InputError(scene.path, "effects", "lens_distortion cannot be left out: the calibration has lens "
                                                "distortion and the labels must follow the real lens")
    decisions = [EffectDecision("lens_distortion", distorted,
                                "the calibration has non-zero distortion" if distorted
                                else "the calibration has no distortion")]
    has_sun = lighting.sun_strength > 0 and lighting.sun_elevation_deg > 0
    if explicit is None:
        shadows = EffectDecision("shadows", has_sun, "the light has a directional sun component" if has_sun
                                 else "the light has no direct sun")
    else:
        wanted = "shadows" in explicit
        shadows = EffectDecision("shadows", wanted, "listed in the scene's effects" if wanted
                                 else "not listed in the scene's effects")
    decisions.append(shadows)
    decisions.extend(EffectDecision(name, False, reason) for name, reason in NOT_SIMULATED.items())
    return decisions


def effect_on(decisions: list[EffectDecision], name: str) -> bool:
    return any(decision.on for decision in decisions if decision.name == name)
