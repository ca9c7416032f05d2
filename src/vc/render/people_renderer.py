"""Render people into one region's view: one fixed Mitsuba scene, rays only where people and their shadows are.

Speed comes from two things (docs/design.md, "Rendering"):

* **Nothing is recompiled per sample.** The scene (layout, sun, sky and ``max_people`` mesh slots of the body
  topology) is built once per region; a sample only rewrites slot vertex positions and colours through
  ``mi.traverse`` and passes its seed as an opaque value, so Dr.Jit reuses the same kernels.
* **Rays go only where a sample differs from the background.** The background is a real photograph; a person
  changes only the pixels it covers and those its shadow darkens. The renderer projects each person's mesh, its
  shadow on the ground and a disc around its feet into the image, and traces ``spp`` rays per pixel of those
  windows only, through the region's fixed sensor (the real intrinsics, principal point included).

Per traced sub-pixel ray the kernel records: the person slot it hits first (obstacles and other people occlude),
that person's path-traced radiance, and — where it hits the static scene — whether the sun and one
cosine-distributed sky direction are visible with and without people. A pixel-centre ray gives the depth pass.
The pixel layers (:class:`Passes`) then follow with box-filter weights:

* ``beauty``: premultiplied person radiance (linear), ``alpha`` its coverage, ``coverage`` per person;
* ``shadow``: the ratio by which people dim the background, per colour channel (the sun's and the sky's
  irradiance, with people over without, on the same rays: exactly 1 wherever no person is in the way);
* ``depth``: camera z of the first surface through each pixel centre (inf: nothing), the static scene's
  depth outside the windows.

Cameras with lens distortion are rendered through :func:`vc.render.sensor.ideal_view` and warped, so every
layer comes out in the region camera's own pixels.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from vc.calibration.camera import Camera
from vc.calibration.lighting import Illumination
from vc.render.layout_scene import layout_scene_dict
from vc.render.mitsuba_setup import mitsuba
from vc.render.sensor import film_position, ideal_view, perspective_sensor
from vc.scenes.layout import Layout

#: Where unused person slots are parked: far below the ground, out of every view and shadow ray.
PARKED_Z_M = -1.0e4
#: Pixels added around each projected window (the box filter and a vertex subsample can reach one pixel out).
WINDOW_MARGIN_PX = 3
#: Radius (m) around the feet in which a person darkens the ground by hiding part of the sky.
CONTACT_SHADOW_RADIUS_M = 0.6
#: Every n-th mesh vertex is projected to size the windows (plus the margin); plenty for a closed body mesh.
WINDOW_VERTEX_STRIDE = 4
#: Offset (m) of secondary rays from the surface they start on, against self-intersection.
RAY_EPSILON_M = 1.0e-3


@dataclass(frozen=True)
class PersonGeometry:
    """One posed person in world coordinates, in the renderer's body topology."""

    vertices: np.ndarray  # (V, 3) float32, metres
    albedo: np.ndarray  # (V, 3) float32, linear diffuse albedo per vertex


@dataclass(frozen=True)
class Passes:
    """The layers of one sample in the region camera's pixels (see the module docstring)."""

    beauty: np.ndarray  # (H, W, 3) float32, premultiplied
    alpha: np.ndarray  # (H, W) float32
    coverage: np.ndarray  # (H, W, P) float32, one channel per person in the order given
    shadow: np.ndarray  # (H, W, 3) float32
    depth: np.ndarray  # (H, W) float32
    traced_pixels: int  # pixels of the ideal image that were traced
    timings: dict[str, float]  # seconds per step of the render (filled in as it goes)


class _Clock:
    """Seconds spent per named step, for the throughput benchmark and the run summary."""

    def __init__(self) -> None:
        self.laps: dict[str, float] = {}
        self._mark = time.perf_counter()

    def lap(self, name: str) -> None:
        now = time.perf_counter()
        self.laps[name] = self.laps.get(name, 0.0) + now - self._mark
        self._mark = now


def ground_shadow_points(points: np.ndarray, towards_sun: np.ndarray) -> np.ndarray:
    """Where the sun's rays through ``points`` (N, 3) meet the ground z = 0."""
    return points - points[:, 2:3] / towards_sun[2] * towards_sun[None, :]


class PeopleRenderer:
    """A region's Mitsuba scene with ``max_people`` body slots, rendering :class:`Passes` per sample.

    ``camera`` is the region's camera (the scene camera cropped and resized to the network input), ``faces``
    the body topology shared by every person.
    """

    def __init__(self, camera: Camera, layout: Layout, illumination: Illumination, faces: np.ndarray, vertex_count: int,
                 max_people: int, spp: int, shadows: bool = True, texture_seed: int = 0) -> None:
        if spp < 1:
            raise ValueError(f"samples per pixel must be at least 1, got {spp}")
        mi = mitsuba()
        self.camera, self.spp, self.max_people, self.vertex_count = camera, spp, max_people, vertex_count
        self.shadows = shadows
        # OptiX (the CUDA variant's ray tracer) traces one scene per kernel: a kernel that also tests rays against
        # the people-free scene gets those tests switched off ("more than one OptiX shader binding table";
        # docs/decisions/0008-compile-time.md). There the static scene's tests run in a kernel of their own;
        # Embree (the CPU variant) has no such limit and keeps one kernel, and its bytes.
        self.one_scene_per_kernel = mi.variant().startswith("cuda")
        self.view = ideal_view(camera)
        ideal = self.view.ideal
        scene_dict = layout_scene_dict(layout, illumination, perspective_sensor(ideal, spp), seed=texture_seed)
        static_dict = {key: value for key, value in scene_dict.items()
                       if key not in ("integrator", "sensor", "sun", "sky")}
        self.slot_keys = [f"person_{index}" for index in range(max_people)]
        parked = self._parked_vertices()
        for key in self.slot_keys:
            scene_dict[key] = self._person_mesh(key, faces, parked)
        self.scene = mi.load_dict(scene_dict)
        self.static_scene = mi.load_dict(static_dict)
        self.params = mi.traverse(self.scene)
        self.sensor = self.scene.sensors()[0]
        self.sampler = mi.load_dict({"type": "independent"})
        self._slot_lookup = self._slot_lookup_table()
        self._active = [False] * max_people

        has_sun = illumination.has_sun
        self.towards_sun = illumination.towards_sun() if has_sun else None
        self.sun_irradiance = np.array(illumination.sun_rgb) * (1.0 if has_sun else 0.0)
        # Without a sun its terms are zero; a direction is kept so that the kernel is the same either way.
        self.sun_vector = self.towards_sun if has_sun else np.array([0.0, 0.0, 1.0])
        self.sky_irradiance = np.array(illumination.sky_rgb)
        self.overcast_sky = illumination.sky_model == "cie_overcast"
        self.forward = camera.R[2]
        self.static_depth = self._static_depth()
        self.static_depth_real = self.view.warp(self.static_depth, cv2.INTER_NEAREST)

    # --- set-up ---------------------------------------------------------------------------------------------
    def _parked_vertices(self) -> np.ndarray:
        parked = np.zeros((self.vertex_count, 3), np.float32)
        parked[:, 2] = PARKED_Z_M
        return parked

    def _person_mesh(self, key: str, faces: np.ndarray, vertices: np.ndarray):
        mi = mitsuba()
        props = mi.Properties()
        props["bsdf"] = mi.load_dict({"type": "diffuse",
                                      "reflectance": {"type": "mesh_attribute", "name": "vertex_color"}})
        mesh = mi.Mesh(key, self.vertex_count, len(faces), props=props, has_vertex_normals=False)
        mesh.add_attribute("vertex_color", 3, mi.Float(np.full(self.vertex_count * 3, 0.5, np.float32)))
        params = mi.traverse(mesh)
        params["faces"] = mi.UInt32(np.ascontiguousarray(faces, dtype=np.uint32).ravel())
        params["vertex_positions"] = mi.Float(np.ascontiguousarray(vertices, dtype=np.float32).ravel())
        params.update()
        return mesh

    def _slot_lookup_table(self):
        """Shape registry id -> person slot (-1 for every other shape and for misses, whose id is 0)."""
        mi = mitsuba()
        import drjit as dr

        def registry_id(shape) -> int:
            return int(dr.reinterpret_array(mi.UInt32, mi.ShapePtr(shape))[0])

        # Every shape's id must be inside the table: an out-of-range gather would read slot 0.
        table = np.full(max(registry_id(shape) for shape in self.scene.shapes()) + 1, -1, np.int32)
        for shape in self.scene.shapes():
            if shape.id() in self.slot_keys:
                table[registry_id(shape)] = self.slot_keys.index(shape.id())
        return mi.Int32(table)

    def _centre_rays(self, xs: np.ndarray, ys: np.ndarray):
        mi = mitsuba()
        ideal = self.view.ideal
        film = film_position(np.stack([xs, ys], axis=-1)) / np.array([ideal.width, ideal.height])
        position = mi.Point2f(mi.Float(film[:, 0].astype(np.float32)), mi.Float(film[:, 1].astype(np.float32)))
        ray, _ = self.sensor.sample_ray(0.0, 0.5, position, mi.Point2f(0.5, 0.5))
        return ray

    def _camera_depth(self, scene, ray) -> np.ndarray:
        mi = mitsuba()
        import drjit as dr

        si = scene.ray_intersect(ray)
        forward = mi.Vector3f(*(float(c) for c in self.forward))
        centre = mi.Point3f(*(float(c) for c in self.camera.center))
        # Measured from the camera centre: the sensor starts its rays on the near clipping plane, not there.
        depth = dr.select(si.is_valid(), dr.dot(si.p - centre, forward), dr.inf)
        return np.asarray(depth, dtype=np.float32)

    def _static_depth(self) -> np.ndarray:
        """Depth through every pixel centre of the ideal image with no people in it (computed once)."""
        ideal = self.view.ideal
        ys, xs = np.indices((ideal.height, ideal.width)).reshape(2, -1)
        return self._camera_depth(self.static_scene, self._centre_rays(xs, ys)).reshape(ideal.height, ideal.width)

    # --- per sample -----------------------------------------------------------------------------------------
    def _place(self, people: Sequence[PersonGeometry]) -> None:
        mi = mitsuba()
        if len(people) > self.max_people:
            raise ValueError(f"{len(people)} people in one sample, the renderer has {self.max_people} slots")
        changed = False
        for slot, key in enumerate(self.slot_keys):
            if slot < len(people):
                person = people[slot]
                self.params[f"{key}.vertex_positions"] = mi.Float(np.ascontiguousarray(person.vertices,
                                                                                       np.float32).ravel())
                self.params[f"{key}.vertex_color"] = mi.Float(np.ascontiguousarray(person.albedo, np.float32).ravel())
                self._active[slot] = changed = True
            elif self._active[slot]:
                self.params[f"{key}.vertex_positions"] = mi.Float(self._parked_vertices().ravel())
                self._active[slot], changed = False, True
        if changed:
            self.params.update()

    def _window_points(self, person: PersonGeometry) -> np.ndarray:
        """World points whose projections bound everything a person changes: body, sun shadow, contact shadow."""
        body = person.vertices[::WINDOW_VERTEX_STRIDE]
        feet = body[np.argmin(body[:, 2])]
        angles = np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False)
        disc = np.stack([feet[0] + CONTACT_SHADOW_RADIUS_M * np.cos(angles),
                         feet[1] + CONTACT_SHADOW_RADIUS_M * np.sin(angles), np.zeros_like(angles)], axis=-1)
        if not self.shadows:
            return body.astype(np.float64)
        parts = [body, disc]
        if self.towards_sun is not None:
            parts.append(ground_shadow_points(body, self.towards_sun))
        return np.concatenate(parts).astype(np.float64)

    def _window_mask(self, people: Sequence[PersonGeometry]) -> np.ndarray:
        """Pixels of the ideal image to trace: the convex hull of each person's window points, plus a margin.

        A hull (rather than a box) keeps a long sun shadow from pulling in the whole rectangle around it.
        """
        ideal = self.view.ideal
        mask = np.zeros((ideal.height, ideal.width), np.uint8)
        for person in people:
            projection = ideal.project(self._window_points(person))
            uv = projection.uv[projection.in_front]
            if len(uv) == 0:
                continue
            # Far outside the image the hull is clipped anyway; bound the coordinates for OpenCV's int32 maths.
            uv = np.clip(uv, -4 * ideal.width, 5 * max(ideal.width, ideal.height))
            hull = cv2.convexHull(np.round(uv * 16).astype(np.int32))
            cv2.fillConvexPoly(mask, hull, 1, lineType=cv2.LINE_8, shift=4)
            cv2.polylines(mask, [hull], True, 1, thickness=2 * WINDOW_MARGIN_PX + 1, shift=4)
        return mask.astype(bool)

    def _trace(self, xs: np.ndarray, ys: np.ndarray, seed: int) -> dict[str, np.ndarray]:
        """Trace ``spp`` jittered rays per pixel and sum each pixel's rays in the kernel (see :meth:`_shade`)."""
        mi = mitsuba()
        import drjit as dr

        ideal, spp = self.view.ideal, self.spp
        self.sampler.seed(dr.opaque(mi.UInt32, seed & 0xFFFFFFFF), len(xs) * spp)
        corner = film_position(np.stack([xs, ys], axis=-1)) - 0.5
        film_x = mi.Float(np.repeat(corner[:, 0], spp).astype(np.float32))
        film_y = mi.Float(np.repeat(corner[:, 1], spp).astype(np.float32))
        jitter = self.sampler.next_2d()
        position = mi.Point2f((film_x + jitter.x) / ideal.width, (film_y + jitter.y) / ideal.height)
        ray, _ = self.sensor.sample_ray(0.0, 0.5, position, mi.Point2f(0.5, 0.5))
        per_ray = self._shade(ray)
        # One kernel for all rays first: reducing unevaluated values would re-trace the rays once per output.
        dr.eval(*per_ray.values())
        sums = {key: dr.block_sum(value, spp) for key, value in per_ray.items()}
        dr.eval(*sums.values())
        result = {key: np.asarray(value, dtype=np.float64) for key, value in sums.items()}
        result["depth"] = self._camera_depth(self.scene, self._centre_rays(xs, ys))
        return result

    def _slot(self, si):
        mi = mitsuba()
        import drjit as dr

        slot = dr.gather(mi.Int32, self._slot_lookup, dr.reinterpret_array(mi.UInt32, si.shape), si.is_valid())
        return dr.select(si.is_valid(), slot, -1)

    def _shade(self, ray) -> dict:
        """Per-ray values: person coverage and radiance, and the static scene's irradiance with/without people.

        People are Lambertian and lit by the sun (one shadow ray) and the sky (one cosine-distributed ray, which
        also picks up one bounce of light off whatever it hits: ground, obstacle or another person), the sky
        with its own distribution (uniform, or the CIE overcast sky's brighter zenith). The same
        two rays from points of the static scene measure how much of the sun and the sky the people hide, so
        the shadow pass costs no extra rays for the sun and sky, only the people-free visibility tests.
        """
        mi = mitsuba()
        import drjit as dr

        si = self.scene.ray_intersect(ray)
        slot = self._slot(si)
        is_person = slot >= 0
        on_static = si.is_valid() & ~is_person
        normal = dr.select(dr.dot(si.n, ray.d) > 0, -si.n, si.n)
        origin = si.p + normal * RAY_EPSILON_M
        sun = mi.Vector3f(*(float(c) for c in self.sun_vector))
        sun_cosine = dr.maximum(dr.dot(normal, sun), 0.0)
        sun_ray = mi.Ray3f(origin, sun)
        sun_open = si.is_valid() & (sun_cosine > 0) & ~self.scene.ray_test(sun_ray, active=si.is_valid())
        sun_irradiance = mi.Color3f(*(float(c) for c in self.sun_irradiance)) * sun_cosine

        sky_ray = mi.Ray3f(origin, mi.Frame3f(normal).to_world(mi.warp.square_to_cosine_hemisphere(
            self.sampler.next_2d())))
        bounce = self.scene.ray_intersect(sky_ray, active=si.is_valid())
        sky_open = si.is_valid() & ~bounce.is_valid()

        # Light arriving along the sky ray: the sky itself, or what the surface it hits reflects (lit by an
        # unshadowed-by-sky, sun-shadow-tested estimate: one bounce).
        # The CIE overcast sky is brighter towards the zenith (vc.calibration.lighting.sky_gradation); the
        # same weight goes on the shadow pass's sky terms, so the ground's sky irradiance stays ``sky`` on average.
        gradation = (3.0 / 7.0) * (1.0 + 2.0 * dr.maximum(sky_ray.d.z, 0.0)) if self.overcast_sky else 1.0
        sky_radiance = mi.Color3f(*(float(c) for c in self.sky_irradiance / np.pi)) * gradation
        bounce_normal = dr.select(dr.dot(bounce.n, sky_ray.d) > 0, -bounce.n, bounce.n)
        bounce_cosine = dr.maximum(dr.dot(bounce_normal, sun), 0.0)
        bounce_lit = is_person & bounce.is_valid() & (bounce_cosine > 0)
        bounce_sun_open = bounce_lit & ~self.scene.ray_test(
            mi.Ray3f(bounce.p + bounce_normal * RAY_EPSILON_M, sun), active=bounce_lit)
        bounce_albedo = bounce.bsdf().eval_diffuse_reflectance(bounce, is_person & bounce.is_valid())
        bounced = bounce_albedo / dr.pi * (
            mi.Color3f(*(float(c) for c in self.sun_irradiance)) * dr.select(bounce_sun_open, bounce_cosine, 0.0)
            + mi.Color3f(*(float(c) for c in self.sky_irradiance)))
        incoming = dr.select(sky_open, sky_radiance, dr.select(bounce.is_valid(), bounced, 0.0))
        albedo = si.bsdf().eval_diffuse_reflectance(si, is_person)
        radiance = albedo * (sun_irradiance * dr.select(sun_open, 1.0, 0.0) / dr.pi + incoming)
        radiance = dr.select(is_person, radiance, 0.0)

        values = {"radiance_r": radiance.x, "radiance_g": radiance.y, "radiance_b": radiance.z}
        if self.shadows:
            if self.one_scene_per_kernel:
                dr.eval(radiance, slot, sun_open, sky_open, sun_cosine, on_static, gradation,
                        sun_ray.o, sun_ray.d, sky_ray.o, sky_ray.d)
            sun_closed_static = self.static_scene.ray_test(sun_ray, active=on_static & (sun_cosine > 0))
            sky_closed_static = self.static_scene.ray_test(sky_ray, active=on_static)
            values["sun_with"] = dr.select(on_static & sun_open, sun_cosine, 0.0)
            values["sun_without"] = dr.select(on_static & (sun_cosine > 0) & ~sun_closed_static, sun_cosine, 0.0)
            values["sky_with"] = dr.select(on_static & sky_open, gradation, 0.0)
            values["sky_without"] = dr.select(on_static & ~sky_closed_static, gradation, 0.0)
        for index in range(self.max_people):
            values[f"slot_{index}"] = dr.select(slot == index, 1.0, 0.0)
        return values

    def render(self, people: Sequence[PersonGeometry], seed: int) -> Passes:
        """The passes of ``people`` (at most ``max_people``) in this region's view; ``seed`` fixes the noise.

        Only the bounding box of the traced windows is filled and warped; the rest of every layer is its
        no-people value (no radiance, no coverage, no shadow, the static depth).
        """
        clock = _Clock()
        self._place(people)
        clock.lap("update_scene")
        height, width, count = self.camera.height, self.camera.width, len(people)
        beauty = np.zeros((height, width, 3), np.float32)
        coverage = np.zeros((height, width, count), np.float32)
        shadow = np.ones((height, width, 3), np.float32)
        depth = self.static_depth_real.copy()
        ys, xs = np.nonzero(self._window_mask(people)) if count else (np.zeros(0, int), np.zeros(0, int))
        clock.lap("windows")
        if len(xs):
            traced = self._trace(xs, ys, seed)
            clock.lap("trace")
            ideal = self.view.ideal
            x0, y0 = max(xs.min() - 1, 0), max(ys.min() - 1, 0)
            x1, y1 = min(xs.max() + 2, ideal.width), min(ys.max() + 2, ideal.height)
            rows, columns = ys - y0, xs - x0
            window = (y1 - y0, x1 - x0)
            window_beauty = np.zeros((*window, 3), np.float32)
            window_beauty[rows, columns] = np.stack([traced[f"radiance_{c}"] for c in "rgb"], axis=-1) / self.spp
            window_coverage = np.zeros((*window, count), np.float32)
            for index in range(count):
                window_coverage[rows, columns, index] = traced[f"slot_{index}"] / self.spp
            window_shadow = np.ones((*window, 3), np.float32)
            if self.shadows:
                window_shadow[rows, columns] = self._shadow_ratio(traced)
            window_depth = np.full(window, np.nan, np.float32)
            window_depth[rows, columns] = traced["depth"]
            clock.lap("layers")
            warp = self.view.warp_window
            for layer, window_layer, outside in ((beauty, window_beauty, 0.0), (coverage, window_coverage, 0.0),
                                                 (shadow, window_shadow, 1.0)):
                area, values = warp(window_layer, x0, y0, outside=outside)
                layer[area] = values
            area, traced_depth = warp(window_depth, x0, y0, cv2.INTER_NEAREST, outside=np.nan)
            depth[area] = np.where(np.isnan(traced_depth), depth[area], traced_depth)
            clock.lap("distortion_warp")
        return Passes(beauty=beauty, alpha=coverage.sum(axis=-1), coverage=coverage, shadow=shadow, depth=depth,
                      traced_pixels=len(xs), timings=clock.laps)

    def _shadow_ratio(self, traced: dict[str, np.ndarray]) -> np.ndarray:
        """Irradiance with people over without, per colour, from each pixel's static-scene rays (1 if none)."""
        def irradiance(case: str) -> np.ndarray:
            return (traced[f"sky_{case}"][:, None] * self.sky_irradiance
                    + traced[f"sun_{case}"][:, None] * self.sun_irradiance)

        with_people, without = irradiance("with"), irradiance("without")
        ratio = np.ones_like(without)
        lit = without > 0
        ratio[lit] = with_people[lit] / without[lit]
        return ratio.astype(np.float32)
