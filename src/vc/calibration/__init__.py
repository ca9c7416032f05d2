"""Camera models (pinhole + Brown–Conrady, Tsai) and the readers of calibration files."""

from vc.calibration.camera import Camera, GroundHit, Projection, camera_from_dict
from vc.calibration.distortion import BrownConrady, NoDistortion, TsaiRadial

__all__ = ["BrownConrady", "Camera", "GroundHit", "NoDistortion", "Projection", "TsaiRadial", "camera_from_dict"]
