"""The scene description (YAML) as pydantic models: every field typed and validated.

See docs/design.md, "Scene description". Paths are kept as written; :mod:`vc.scenes.loader` resolves them relative
to the YAML file and turns validation errors into one line naming the file and the field.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, AwareDatetime, Discriminator, Field, Tag, field_validator, model_validator

from vc.calibration.readers import READERS, UNIT_SCALE
from vc.scenes.layout import Layout, StrictModel, Vec2, validate_ground_polygon
from vc.scenes.pixel_layout import PixelLayout

Matrix3 = Annotated[list[Annotated[list[float], Field(min_length=3, max_length=3)]], Field(min_length=3,
                                                                                          max_length=3)]
Size = Annotated[list[Annotated[int, Field(gt=0)]], Field(min_length=2, max_length=2)]

#: Camera responses accepted: sRGB, linear, a pure gamma ("gamma 2.2"), or ``auto`` (fitted on the background
#: where it shows one, :mod:`vc.calibration.response_fit`).
RESPONSE_PATTERN = re.compile(r"^(srgb|linear|auto|gamma\s+\d+(\.\d+)?)$")
#: Effects the renderer knows (docs/design.md "Effects"); ``auto`` lets the scene decide which it needs.
EFFECT_NAMES = ("lens_distortion", "shadows", "sun_course", "motion_blur", "optical_blur", "vignetting",
                "sensor_noise", "jpeg", "defocus")


def _response(value: str) -> str:
    if not RESPONSE_PATTERN.match(value.strip().lower()):
        raise ValueError(f"unknown camera response {value!r} (expected srgb, linear, 'gamma G' or auto)")
    return value.strip().lower()


Response = Annotated[str, AfterValidator(_response)]


class DistortionSpec(StrictModel):
    model: Literal["none", "opencv", "tsai"] = "none"
    k: list[float] | None = None
    kappa: float | None = None

    @model_validator(mode="after")
    def _coefficients(self) -> DistortionSpec:
        if self.model == "opencv" and (self.k is None or len(self.k) not in (4, 5)):
            raise ValueError("opencv distortion needs k: [k1, k2, p1, p2] or [k1, k2, p1, p2, k3]")
        if self.model == "tsai" and self.kappa is None:
            raise ValueError("tsai distortion needs kappa (normalised units)")
        if self.k is not None and not np.isfinite(self.k).all():
            raise ValueError("distortion coefficients must be finite")
        return self


class InlineCamera(StrictModel):
    """A camera written out in the scene: ``K``, distortion, and ``R``/``t`` (world -> camera, metres)."""

    size: Size
    K: Matrix3
    distortion: DistortionSpec = DistortionSpec()
    R: Matrix3 | None = None
    rvec: Annotated[list[float], Field(min_length=3, max_length=3)] | None = None
    t: Annotated[list[float], Field(min_length=3, max_length=3)]
    response: Response = "srgb"
    exposure_s: float | None = Field(None, gt=0, le=1)  # exposure time, when known: decides motion blur

    @model_validator(mode="after")
    def _one_rotation(self) -> InlineCamera:
        if (self.R is None) == (self.rvec is None):
            raise ValueError("give exactly one of R (3x3) or rvec (Rodrigues vector)")
        return self

    def rotation(self) -> np.ndarray:
        if self.R is not None:
            return np.asarray(self.R, dtype=np.float64)
        import cv2  # the same Rodrigues conversion the OpenCV calibration reader uses

        return cv2.Rodrigues(np.asarray(self.rvec, dtype=np.float64).reshape(3, 1))[0]


class CalibrationRef(StrictModel):
    """A calibration file next to the scene, in one of the formats of :mod:`vc.calibration.readers`."""

    format: str
    path: Path
    size: Size | None = None
    units: str | None = None
    focal_px: float | None = Field(None, gt=0)  # ground-points / homography: the focal length, when known
    response: Response = "srgb"
    exposure_s: float | None = Field(None, gt=0, le=1)  # exposure time, when known: decides motion blur
    #: ``people``: measured ground points ``[u, v, x, y]`` (pixel, then ground position in ``units``) that refine
    #: the people's camera (vc.calibration.points_and_people); ``vc-scene init --points`` and the editor write them.
    points: list[tuple[float, float, float, float]] | None = None

    @model_validator(mode="after")
    def _points_refine_people(self) -> CalibrationRef:
        if self.points is not None and self.format != "people":
            raise ValueError(f"points refine a camera solved from people (format: people); a {self.format} "
                             f"calibration takes none")
        return self

    @field_validator("format")
    @classmethod
    def _known_format(cls, value: str) -> str:
        if value not in READERS:
            raise ValueError(f"unknown calibration format {value!r} (expected one of {', '.join(sorted(READERS))})")
        return value

    @field_validator("units")
    @classmethod
    def _known_units(cls, value: str | None) -> str | None:
        if value is not None and value not in UNIT_SCALE:
            raise ValueError(f"unknown units {value!r} (expected one of {', '.join(UNIT_SCALE)})")
        return value


class VonMises(StrictModel):
    mean_deg: float
    kappa: float = Field(ge=0)
    weight: float = Field(1.0, gt=0)


class Priors(StrictModel):
    """What is known about the people of this scene; defaults cover adults walking anywhere."""

    orientation: Literal["uniform"] | Annotated[list[VonMises], Field(min_length=1)] = "uniform"
    height_m: Annotated[list[Annotated[float, Field(gt=0.5, lt=2.6)]], Field(min_length=2, max_length=2)] = [
        1.5, 1.95]
    #: The chance that a person placed in a sample walks with others: a group of 2-4 side by side or in file
    #: (render/placement.py). 0 places everyone on their own.
    group_rate: float = Field(0.0, ge=0.0, le=1.0)
    #: Ground per person where the scene is at its busiest (m2): about 40 for a quiet plaza (the default), 10 for
    #: a busy pavement, 3 for a crowd. Sets how many people a sample holds (render/placement.py).
    m2_per_person: float = Field(40.0, ge=1.0)
    #: What the people wear (render/appearance.py WARDROBES): ``mixed`` street clothing of a mild day (the
    #: default), ``winter`` coats (mostly black, grey and navy; a third with a hat or hood) or ``summer``.
    clothing: Literal["mixed", "winter", "summer"] = "mixed"

    @field_validator("height_m")
    @classmethod
    def _ordered(cls, value: list[float]) -> list[float]:
        if value[0] >= value[1]:
            raise ValueError(f"height_m must be [low, high] with low < high, got {value}")
        return value


class Lighting(StrictModel):
    """Explicit sun and sky (``lighting: auto`` estimates them from the background image instead)."""

    sun_azimuth_deg: float = 135.0
    sun_elevation_deg: float = Field(45.0, ge=-10, le=90)
    sun_strength: float = Field(3.0, ge=0)
    sky_strength: float = Field(1.0, ge=0)


class SolarLighting(StrictModel):
    """Where and when the background was taken: the sun's direction follows from them (a solar-position
    library); its strength and the sky are still estimated from the background."""

    location: Annotated[list[float], Field(min_length=2, max_length=2)]  # [latitude, longitude], degrees
    time: AwareDatetime  # ISO 8601 with its UTC offset, e.g. 2009-03-20T10:30:00+00:00
    north_deg: float  # where geographic north points in the scene: degrees from +x towards +y

    @field_validator("location")
    @classmethod
    def _on_earth(cls, value: list[float]) -> list[float]:
        latitude, longitude = value
        if not (-90.0 <= latitude <= 90.0 and -180.0 <= longitude <= 180.0):
            raise ValueError(f"location must be [latitude, longitude] in degrees, got {value}")
        return value


def _lighting_kind(value) -> str:
    """Which form a ``lighting:`` entry takes, so that a mistake is reported against that form alone."""
    if isinstance(value, str):
        return "auto"
    if isinstance(value, dict) and {"location", "time", "north_deg"} & value.keys() or isinstance(value, SolarLighting):
        return "solar"
    return "explicit"


#: ``lighting:``: ``auto`` (estimated from the background), explicit sun and sky, or where and when (solar).
LightingSpec = Annotated[Annotated[Literal["auto"], Tag("auto")] | Annotated[Lighting, Tag("explicit")]
                         | Annotated[SolarLighting, Tag("solar")], Discriminator(_lighting_kind)]


class NamedPolygon(StrictModel):
    name: str = Field(pattern=r"^[A-Za-z0-9_-]+$")
    polygon: list[Vec2]

    @field_validator("polygon")
    @classmethod
    def _simple(cls, value: list[list[float]]) -> list[list[float]]:
        validate_ground_polygon(value)
        return value


class ZoneSpec(NamedPolygon):
    """A named zone a service reports people entering and leaving (by their feet; :mod:`vc.deploy.zones`): a polygon
    on the ground in metres (``frame: ground``, the default) or drawn in pixels of the background (``frame: image``).
    Zones change nothing that is rendered or trained: they travel into the bundle at export."""

    frame: Literal["ground", "image"] = "ground"


class RegionPlanSpec(StrictModel):
    """How the walkable area is split into regions, each with its own network (docs/design.md "Regions").

    ``auto`` cuts depth bands in which the height of a ``reference_height_m`` person in pixels varies by at most
    ``max_height_ratio``; ``single`` is the paper's SPN-G (one region for everything); ``explicit`` takes the
    ground ``polygons`` as given.
    """

    mode: Literal["auto", "single", "explicit"] = "auto"
    max_height_ratio: float = Field(1.6, gt=1.0)
    reference_height_m: float = Field(1.75, gt=0.5, lt=2.6)
    target_person_px: float = Field(80.0, ge=16)
    # Per region (by its name: r0, r1, ... far to near under auto), a person size that replaces target_person_px:
    # where people are big enough to show which way they face, their left and right can be learned (PETS09: at
    # 48 px not at all, docs/pose.md), at the runtime a larger input costs.
    person_px_by_region: dict[str, Annotated[float, Field(ge=16)]] = {}
    min_person_px: float = Field(16.0, gt=0)
    max_upscale: float = Field(2.0, ge=1.0)
    margin_px: int = Field(8, ge=0)
    input_multiple: int = Field(16, ge=1, le=128)
    polygons: list[NamedPolygon] | None = None

    @model_validator(mode="after")
    def _polygons_iff_explicit(self) -> RegionPlanSpec:
        if (self.mode == "explicit") != (self.polygons is not None):
            raise ValueError("polygons are given exactly when mode is explicit")
        if self.polygons is not None:
            names = [p.name for p in self.polygons]
            if len(set(names)) != len(names):
                raise ValueError("region names must be unique")
        return self


def _layout_frame(value: object) -> str:
    frame = value.get("frame") if isinstance(value, dict) else getattr(value, "frame", "ground")
    return "image" if frame == "image" else "ground"


#: A layout in metres on the ground (the default) or drawn in pixels of the background (``frame: image``).
LayoutSpec = Annotated[Annotated[Layout, Tag("ground")] | Annotated[PixelLayout, Tag("image")],
                       Discriminator(_layout_frame)]


class SceneFile(StrictModel):
    """The whole scene YAML."""

    name: str = Field(pattern=r"^[A-Za-z0-9_.-]+$")
    image: Path
    video: Path | None = None  # frames of the same camera (a video file or a folder of images): noise, compression
    camera: InlineCamera | None = None
    calibration: CalibrationRef | None = None
    layout: LayoutSpec
    priors: Priors = Priors()
    lighting: LightingSpec = "auto"
    effects: Literal["auto"] | list[Literal[EFFECT_NAMES]] = "auto"  # type: ignore[valid-type]
    regions: RegionPlanSpec = RegionPlanSpec()
    zones: list[ZoneSpec] = []

    @field_validator("zones")
    @classmethod
    def _unique_zone_names(cls, value: list[ZoneSpec]) -> list[ZoneSpec]:
        names = [zone.name for zone in value]
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise ValueError(f"zone names must be unique: {', '.join(repeated)} repeated")
        return value

    @field_validator("regions", mode="before")
    @classmethod
    def _regions_shorthand(cls, value):
        """``regions: auto`` / ``single`` / a list of named polygons are shorthands for the full spec."""
        if isinstance(value, str):
            if value not in ("auto", "single"):
                raise ValueError(f"expected auto, single, a mapping or a list of regions, got {value!r}")
            return {"mode": value}
        if isinstance(value, list):
            return {"mode": "explicit", "polygons": value}
        return value

    @model_validator(mode="after")
    def _one_camera(self) -> SceneFile:
        if (self.camera is None) == (self.calibration is None):
            raise ValueError("give exactly one of camera (inline) or calibration (a file)")
        return self
