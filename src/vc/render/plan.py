"""What every sample of a scene is rendered with, decided once per render: the light and the camera effects.

``vc-render`` prints this plan and writes it into the dataset manifest; every region's synthesizer is built
from it, so all samples of a dataset share one light and one camera.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import cv2

from vc.calibration.lighting import Illumination
from vc.calibration.response_fit import ResponseFit
from vc.io import read_image
from vc.render.camera_measurements import CameraMeasurements, measure_camera
from vc.render.effects import EffectDecision, Evidence, build_effects, effect_on, plan_effects, time_effect
from vc.render.relight import LightingSolution, solve_lighting
from vc.render.sun_course import SunPosition
from vc.scenes.loader import Scene
from vc.scenes.regions import Region


@dataclass(frozen=True, eq=False)
class RenderPlan:
    """The light and the effects of a scene's samples, with the evidence for them."""

    response: ResponseFit
    lighting: LightingSolution
    camera: CameraMeasurements
    effects: list[EffectDecision]
    seconds: float  # spent making the plan

    @property
    def illumination(self) -> Illumination:
        return self.lighting.illumination

    @property
    def shadows(self) -> bool:
        return effect_on(self.effects, "shadows")

    @property
    def sun_course(self) -> list[SunPosition]:
        """The sun's positions samples are drawn under, the photographed one first (empty: the estimated sun alone)."""
        for decision in self.effects:
            if decision.name == "sun_course" and decision.on:
                return [SunPosition.from_dict(position) for position in decision.parameters["positions"]]
        return []

    def to_dict(self) -> dict:
        return {"response": self.response.to_dict(), "lighting": self.lighting.to_dict(),
                "camera_measurements": self.camera.to_dict(),
                "effects": [decision.to_dict() for decision in self.effects], "seconds": round(self.seconds, 2)}


def region_background(image, region: Region):
    """The region's crop of the full-frame image, resized to the network input bilinearly with half-pixel centres
    (``cv2.INTER_LINEAR``), which is what an ONNX ``Resize`` (linear, ``half_pixel``) does to real frames."""
    crop = region.crop
    window = image[crop.y0:crop.y1, crop.x0:crop.x1]
    return cv2.resize(window, region.input_size, interpolation=cv2.INTER_LINEAR)


def with_costs(decisions: list[EffectDecision], scene: Scene, regions: list[Region]) -> list[EffectDecision]:
    """The decisions with each sample-level effect's cost measured on the largest region (the renderer's own
    effects cost what they add to the render pass, which the render summary's stage times show)."""
    largest = max(regions, key=lambda region: region.input_size[0] * region.input_size[1])
    background = scene.camera_response().response.decode(region_background(read_image(scene.image_path), largest))
    costs = {effect.name: round(time_effect(effect, background), 3)
             for effect in build_effects(decisions, scene, largest)}
    return [replace(decision, ms_per_sample=costs.get(decision.name)) for decision in decisions]


def plan_render(scene: Scene, regions: list[Region], time_costs: bool = True) -> RenderPlan:
    """Resolve the camera response and the light (:func:`vc.render.relight.solve_lighting`), measure the camera,
    decide the effects."""
    started = time.perf_counter()
    response = scene.camera_response()
    lighting = solve_lighting(scene, regions)
    camera = measure_camera(scene)
    decisions = plan_effects(Evidence(scene, regions, lighting.illumination, lighting.fit, camera))
    if time_costs:
        decisions = with_costs(decisions, scene, regions)
    return RenderPlan(response, lighting, camera, decisions, time.perf_counter() - started)
