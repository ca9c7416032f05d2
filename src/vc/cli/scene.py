"""``vc-scene``: check a scene description, draw it over its background, or make a background from a video.

    vc-scene check SCENE [--json OUT.json]
    vc-scene show SCENE -o overlay.png
    vc-scene background VIDEO -o background.png [--frames N]
    vc-scene synthesize SCENE -o background.png [--spp S] [--seed K]
    vc-scene light SCENE -o compare.png [--json OUT.json]
    vc-scene init VIDEO|FRAMES|IMAGE -o DIR [--points P.csv [--no-people] | --calibration FILE [--format F]
             | --mot-world GT.txt] [--focal F] [--frames first:last:step]
    vc-scene calibrate POINTS.csv|H.txt --size W H [--format ground-points|homography] [--focal F] [--units U]
             -o camera.yaml [--json OUT.json]
    vc-scene edit DIR|SCENE [--host H] [--port P]

Bad input (a malformed scene, a missing file, an unreadable video) prints one ``error:`` line naming the file
and the field, and exits with status 2.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from vc import __version__
from vc.cli.common import handles_input_errors
from vc.deploy.frames import FrameRange
from vc.errors import InputError
from vc.io import atomic_directory, read_image, write_image, write_json
from vc.scenes.loader import Scene, load_scene
from vc.scenes.regions import Region, plan_regions


def scene_summary(scene: Scene, regions: list[Region]) -> dict:
    """Everything ``check`` reports, as JSON-ready data."""
    camera = scene.camera
    return {
        "scene": scene.name,
        "path": str(scene.path),
        "content_hash": scene.content_hash,
        "image": str(scene.image_path),
        "camera": {
            **camera.to_dict(),
            "centre_m": [round(float(v), 4) for v in camera.center],
            "response": scene.response,
            "response_fit": scene.camera_response().to_dict() if scene.response == "auto" else None,
        },
        "layout": {
            "walkable_area_m2": round(float(scene.layout.walkable_area().area), 2),
            "obstacles": len(scene.layout.obstacles),
            "walls": len(scene.layout.walls),
        },
        "region_mode": scene.regions.mode,
        "regions": [region.to_dict() for region in regions],
    }


def _print_summary(summary: dict) -> None:
    camera = summary["camera"]
    K = camera["K"]
    width, height = camera["size"]
    print(f"scene   {summary['scene']}  ({summary['path']})")
    print(f"hash    {summary['content_hash'][:16]}")
    print(f"camera  {width}x{height}  fx={K[0][0]:.1f} fy={K[1][1]:.1f} cx={K[0][2]:.1f} cy={K[1][2]:.1f}  "
          f"distortion={camera['distortion']['model']}  height={camera['centre_m'][2]:.2f} m  "
          f"response={camera['response']}")
    if camera["response_fit"] is not None:
        print(f"        response fitted: {camera['response_fit']['name']} ({camera['response_fit']['reason']})")
    layout = summary["layout"]
    print(f"layout  walkable {layout['walkable_area_m2']:.1f} m2, {layout['obstacles']} obstacles, "
          f"{layout['walls']} walls")
    print(f"regions {len(summary['regions'])} ({summary['region_mode']})")
    print(f"  {'name':<8}{'ground m2':>10}  {'crop x,y,w,h':<22}{'input':>10}  {'person px':>12}")
    for region in summary["regions"]:
        x, y, w, h = region["crop_window"]
        low, high = region["person_height_px"]
        print(f"  {region['name']:<8}{region['ground_area_m2']:>10.1f}  {f'{x},{y},{w},{h}':<22}"
              f"{'x'.join(map(str, region['input_size'])):>10}  {f'{low:.0f}-{high:.0f}':>12}")


def cmd_check(args: argparse.Namespace) -> int:
    scene = load_scene(args.scene)
    summary = scene_summary(scene, plan_regions(scene))
    _print_summary(summary)
    if args.json:
        write_json(args.json, summary)
        print(f"wrote {args.json}")
    return 0


def cmd_show(args: argparse.Namespace) -> int:
    from vc.scenes.overlay import draw_overlay

    scene = load_scene(args.scene)
    regions = plan_regions(scene)
    image = draw_overlay(scene, read_image(scene.image_path), regions)
    write_image(args.output, image)
    write_json(args.output.with_suffix(".json"), scene_summary(scene, regions))
    print(f"wrote {args.output} ({len(regions)} regions) and {args.output.with_suffix('.json')}")
    return 0


def cmd_background(args: argparse.Namespace) -> int:
    from vc.evaluation.mot import read_mot_boxes
    from vc.scenes.background import median_background

    started = time.perf_counter()
    people = None if args.people is None else read_mot_boxes(args.people)
    result = median_background(args.video, max_frames=args.frames, progress=sys.stderr.isatty() or None,
                               people=people)
    write_image(args.output, result.image)
    write_json(args.output.with_suffix(".json"), {"video": str(args.video), **result.to_dict(),
                                                  "seconds": round(time.perf_counter() - started, 2)})
    height, width = result.image.shape[:2]
    print(f"wrote {args.output}: {width}x{height}, median of {len(result.frame_indices)} of "
          f"{result.frames_in_video} frames in {time.perf_counter() - started:.1f} s")
    _print_background_cover(result)
    return 0


def _print_background_cover(result) -> None:
    """One line on the people masked out of a median background, and what they left covered."""
    if result.people_masked:
        print(f"         people's boxes left out of the median; {100 * result.never_free_fraction:.1f} % of the image "
              "is covered by someone in every frame (plain median there: look for ghosts)")


def cmd_synthesize(args: argparse.Namespace) -> int:
    from vc.render.background import render_background
    from vc.render.relight import explicit_illumination
    from vc.scenes.schema import Lighting

    if args.spp < 1:
        raise InputError(None, "--spp", f"must be at least 1, got {args.spp}")
    scene = load_scene(args.scene, require_image=False)
    # A background to be made has no image to estimate the light from: the scene's explicit lighting, else the
    # default sun and sky.
    lighting = scene.lighting if isinstance(scene.lighting, Lighting) else Lighting()
    started = time.perf_counter()
    image = render_background(scene.camera, scene.layout, explicit_illumination(lighting), spp=args.spp,
                              seed=args.seed)
    seconds = time.perf_counter() - started
    write_image(args.output, image)
    write_json(args.output.with_suffix(".json"), {
        "scene": scene.name, "method": "Mitsuba path tracing of the layout", "spp": args.spp, "seed": args.seed,
        "size": list(scene.camera.size), "lighting": lighting.model_dump(), "seconds": round(seconds, 2),
    })
    print(f"wrote {args.output}: {scene.camera.width}x{scene.camera.height} at {args.spp} spp in {seconds:.1f} s")
    return 0


def cmd_light(args: argparse.Namespace) -> int:
    from vc.render.relight import estimate_scene_lighting, explicit_illumination, sun_angle_error_deg, write_comparison
    from vc.scenes.schema import Lighting

    scene = load_scene(args.scene)
    regions = plan_regions(scene)
    started = time.perf_counter()
    solution = estimate_scene_lighting(scene, regions)
    write_comparison(scene, regions, solution, args.output)
    result = {"scene": scene.name, **solution.to_dict(), "seconds": round(time.perf_counter() - started, 2)}
    print(f"light  {solution.summary()}")
    print(f"       {solution.estimate.reason}")
    if isinstance(scene.lighting, Lighting):
        given = explicit_illumination(scene.lighting)
        comparison = {"scene_file": given.to_dict()}
        if given.has_sun and solution.illumination.has_sun:
            comparison["sun_direction_error_deg"] = round(sun_angle_error_deg(given, solution.illumination), 2)
        result["compared_with_scene_file"] = comparison
        sun = f"sun {given.sun_to_sky:.2f}x sky" if given.has_sun else "no sun"
        off = (f", sun direction off by {comparison['sun_direction_error_deg']:.1f} deg"
               if "sun_direction_error_deg" in comparison else "")
        print(f"       the scene file gives: {sun}{off} (renders use the scene file's)")
    for fit in solution.fit.regions:
        error = "no known ground" if fit.error is None else f"{fit.error:+.1%}"
        print(f"  {fit.region:<6} background {fit.background:.3f}  re-render {fit.rendered:.3f}  {error}")
    if args.json:
        write_json(args.json, result)
    print(f"wrote {args.output}" + (f" and {args.json}" if args.json else "")
          + f" in {time.perf_counter() - started:.1f} s")
    return 0


def cmd_calibrate(args: argparse.Namespace) -> int:
    from vc.calibration.ground_points import (
        calibrate_from_ground_points,
        read_ground_points,
        write_opencv_yaml,
    )
    from vc.calibration.readers import UNIT_SCALE, read_calibration

    size = tuple(args.size)
    if args.format == "ground-points":
        image, ground = read_ground_points(args.input, UNIT_SCALE[args.units])
        fit = calibrate_from_ground_points(image, ground, size, args.focal, args.input)
        camera, result = fit.camera, fit.to_dict()
        for number, point in enumerate(result["points"], start=1):
            print(f"  point {number}: image ({point['image_px'][0]:.1f}, {point['image_px'][1]:.1f}) px  ground "
                  f"({point['ground_m'][0]:.2f}, {point['ground_m'][1]:.2f}) m  error {point['error_px']:.2f} px")
        print(f"reprojection: median {result['reprojection_px']['median']:.2f} px, max "
              f"{result['reprojection_px']['max']:.2f} px over {len(image)} points")
    else:
        camera = read_calibration(args.input, "homography", size, args.units, args.focal)
        result = {"focal_px": round(float(camera.fx), 3), "focal_solved": args.focal is None,
                  "camera_height_m": round(float(camera.center[2]), 3)}
    solved = "solved" if args.focal is None else "given"
    print(f"camera: focal {camera.fx:.1f} px ({solved}), principal point at the image centre, "
          f"{camera.center[2]:.2f} m above the ground at ({camera.center[0]:.2f}, {camera.center[1]:.2f}) m")
    try:
        write_opencv_yaml(camera, args.output)
    except OSError as error:
        raise InputError(args.output, "", f"cannot write ({error.strerror or error})") from None
    if args.json:
        write_json(args.json, {"input": str(args.input), "format": args.format, "size": list(size), **result,
                               "camera": camera.to_dict()})
    print(f"wrote {args.output}" + (f" and {args.json}" if args.json else "")
          + ": review it, then name it in the scene as calibration: {format: opencv, path: ...}")
    return 0


def cmd_init(args: argparse.Namespace) -> int:
    from vc.scenes.overlay import draw_overlay
    from vc.scenes.starter import make_starter_scene, scene_name

    started, output = time.perf_counter(), args.output
    if output.exists() and (not output.is_dir() or any(output.iterdir())):
        raise InputError(output, "", "exists and is not empty: vc-scene init writes a new scene folder (a scene "
                                     "edited there would be lost); choose another -o")
    # Built in a staging folder beside OUT (same depth: relative paths hold) that becomes OUT only when complete.
    with atomic_directory(output) as staging:
        starter = make_starter_scene(args.input, staging, args.points, args.calibration, args.format,
                                     args.mot_world, args.focal, progress=sys.stderr.isatty(),
                                     name=scene_name(output), frames=args.frames,
                                     with_people=not args.no_people)
        scene = load_scene(starter.scene_path)
        regions = plan_regions(scene)
        write_image(staging / "overlay.png", draw_overlay(scene, read_image(scene.image_path), regions))
        summary = {**scene_summary(scene, regions), **starter.to_dict(), "path": str(output / "scene.yaml"),
                   "image": str(output / "background.png"), "seconds": round(time.perf_counter() - started, 1)}
        write_json(staging / "init.json", summary)
    scene_path, camera = output / "scene.yaml", scene.camera
    print(f"camera   from {starter.calibration_source}: focal {camera.fx:.0f} px, {camera.center[2]:.2f} m above the "
          f"ground")
    if starter.fit is not None:
        errors = starter.fit.errors_px
        taken = f" (taken to {output / starter.ground_points_path.name})" if starter.ground_points_path else ""
        print(f"         reprojection median {np.median(errors):.2f} px, max {errors.max():.2f} px over {len(errors)} "
              f"points{taken}")
    if starter.people is not None:
        from vc.scenes.walker_overlay import solution_lines

        if starter.fit is not None:
            print("         the people alone, which the points refined:")
        for line in solution_lines(starter.people):
            print(f"         {line}")
        print(f"         drawn in {output / 'walkers.png'}: the yellow ticks must sit on the green lines' tops")
    if starter.people_unused is not None:
        print(f"         points alone: {starter.people_unused}")
    if starter.background is not None:
        print(f"background median of {len(starter.background.frame_indices)} frames")
        _print_background_cover(starter.background)
    print(f"regions  {len(regions)}: " + ", ".join(f"{r.name} people {r.person_px[0]:.0f}-{r.person_px[1]:.0f} px"
                                                   for r in regions))
    print(f"wrote    {scene_path}, background.png, overlay.png, init.json in {time.perf_counter() - started:.0f} s")
    print("next     1. look at overlay.png: the figures must stand on the ground, as tall as people there are;\n"
          f"         2. vc-scene edit {output}: trim the walkable polygon, add obstacles and walls (in a browser);\n"
          f"         3. vc-scene light {scene_path} -o light.png  (the light estimated from the background);\n"
          f"         4. vc-compile {scene_path} -o OUT")
    return 0


def cmd_edit(args: argparse.Namespace) -> int:
    from vc.scenes.editor_server import serve

    scene_path = args.scene / "scene.yaml" if args.scene.is_dir() else args.scene
    if not scene_path.is_file():
        raise InputError(args.scene, "", "no scene.yaml here: give a scene folder or its YAML file")
    try:
        server = serve(scene_path, args.host, args.port)
    except OSError as error:  # the port is taken, or the address is not this machine's
        raise InputError(None, "--port", f"cannot serve on {args.host}:{args.port} ({error.strerror or error}): "
                                         "choose another --port, or 0 for any free one") from None
    print(f"editing  {scene_path.resolve()}  (Save writes it; nothing else is written)")
    print(f"open     {server.url}  in a browser on this machine; Ctrl-C stops", flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        print("stopped")
    finally:
        server.server_close()
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc-scene", description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", required=True)

    check = commands.add_parser("check", help="validate a scene and print its camera and regions")
    check.add_argument("scene", type=Path)
    check.add_argument("--json", type=Path, help="also write the summary as JSON here")
    check.set_defaults(run=cmd_check)

    show = commands.add_parser("show", help="draw the scene's geometry over its background")
    show.add_argument("scene", type=Path)
    show.add_argument("-o", "--output", type=Path, required=True, help="overlay PNG (a .json summary beside it)")
    show.set_defaults(run=cmd_show)

    background = commands.add_parser("background", help="temporal-median background image from a video")
    background.add_argument("video", type=Path)
    background.add_argument("-o", "--output", type=Path, required=True)
    background.add_argument("--frames", type=int, default=150, help="frames sampled evenly (default 150)")
    background.add_argument("--people", type=Path, default=None,
                            help="a MOT-format ground truth whose boxes are left out of the median (no ghosts)")
    background.set_defaults(run=cmd_background)

    synthesize = commands.add_parser("synthesize", help="render a background image from the scene's layout")
    synthesize.add_argument("scene", type=Path)
    synthesize.add_argument("-o", "--output", type=Path, required=True)
    synthesize.add_argument("--spp", type=int, default=128, help="samples per pixel (default 128)")
    synthesize.add_argument("--seed", type=int, default=0, help="texture and sampler seed (default 0)")
    synthesize.set_defaults(run=cmd_synthesize)

    light = commands.add_parser("light", help="estimate the light from the background; compare its re-render")
    light.add_argument("scene", type=Path)
    light.add_argument("-o", "--output", type=Path, required=True, help="comparison figure (PNG)")
    light.add_argument("--json", type=Path, help="also write the estimate and the per-region errors as JSON here")
    light.set_defaults(run=cmd_light)

    init = commands.add_parser("init", help="a starting scene from a camera's video (or image) and its "
                                            "calibration, measured ground points, or the people walking through it")
    init.add_argument("input", type=Path, help="video file, folder of frames, or one image")
    init.add_argument("-o", "--output", type=Path, required=True, help="the new scene's folder")
    source = init.add_mutually_exclusive_group()
    source.add_argument("--points", type=Path, help="CSV of u, v, x, y: image points and their ground positions (m)")
    source.add_argument("--calibration", type=Path, help="a calibration file (tsai-xml, towncentre-ci, opencv, ...)")
    source.add_argument("--mot-world", type=Path, help="ground truth with each person's ground position (MOT "
                                                       "frame,id,left,top,width,height,conf,x,y,z): feet as points")
    init.add_argument("--no-people", action="store_true",
                      help="with --points: solve from the points alone, not together with the people walking "
                           "through the video")
    init.add_argument("--format", default=None, help="the calibration file's format (default: from its suffix)")
    init.add_argument("--focal", type=float, default=None, help="focal length in pixels, when known")
    init.add_argument("--frames", type=FrameRange.parse, default=FrameRange(),
                      help="the frames of the video (or folder) to read for the background and the walkers, "
                           "first:last:step (default: all)")
    init.set_defaults(run=cmd_init)

    calibrate = commands.add_parser("calibrate", help="solve the camera from measured ground points or a "
                                                      "homography; write it as OpenCV YAML")
    calibrate.add_argument("input", type=Path, help="CSV of u, v, x, y (ground-points) or a 3x3 image -> ground "
                                                    "homography (homography)")
    calibrate.add_argument("--format", choices=("ground-points", "homography"), default="ground-points")
    calibrate.add_argument("--size", type=int, nargs=2, required=True, metavar=("WIDTH", "HEIGHT"),
                           help="the image size in pixels")
    calibrate.add_argument("--focal", type=float, default=None,
                           help="focal length in pixels, when known (default: solved)")
    calibrate.add_argument("--units", choices=("m", "cm", "mm"), default="m", help="of the ground coordinates")
    calibrate.add_argument("-o", "--output", type=Path, required=True, help="camera YAML (cv::FileStorage)")
    calibrate.add_argument("--json", type=Path, help="also write the solution and each point's error as JSON here")
    calibrate.set_defaults(run=cmd_calibrate)

    edit = commands.add_parser("edit", help="draw the walkable area, obstacles, walls and zones over the background "
                                            "in a browser; Save writes scene.yaml")
    edit.add_argument("scene", type=Path, help="a scene folder (its scene.yaml) or a scene YAML")
    edit.add_argument("--host", default="127.0.0.1", help="the address to serve on (default: this machine only)")
    edit.add_argument("--port", type=int, default=8765, help="the port (default 8765; 0: any free one)")
    edit.set_defaults(run=cmd_edit)
    return parser


@handles_input_errors
def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
