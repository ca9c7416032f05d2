"""Visual Compiler: compile one camera's scene into a pedestrian detector trained only on synthetic renders."""

__version__ = "0.1.0"
