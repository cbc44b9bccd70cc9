"""Scenes and Gaussians on disk and in memory: a scene folder as a `Scene` (images, masks, depth, ground
truth, COLMAP model), COLMAP binary/text reading and writing, PNG/EXR images, Gaussians as tensors and
their .ply, masks, visibility tests, and turning the generator's renders into a scene folder. May import
engine.formats and engine.base."""
