"""Measuring a compiled bundle: metrics, the self-test on composed frames, real-video evaluation against MOT ground
truth beside the baselines, the miss analysis, pose agreement, and the images (overlays, curves) people look at."""
