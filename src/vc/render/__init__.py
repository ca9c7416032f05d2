"""Rendering: the Mitsuba scene of a layout, sensors that reproduce a real camera, and rendered images.

Mitsuba only knows ideal pinhole cameras; everything a real lens adds (anisotropic focal lengths, skew,
distortion) is applied afterwards by resampling (:mod:`vc.render.sensor`), so geometry stays exact.
"""
