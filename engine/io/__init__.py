"""Files that need more than numpy: COLMAP models (pycolmap), PNG/EXR images (OpenCV, OpenImageIO),
Gaussians as tensors and their .ply, masks, extents and visibility tests. May import engine.formats and
engine.base."""
