"""Rendering Gaussians: gsplat on CUDA, the pure-torch reference rasterizer on the CPU, spherical
harmonics, and rendering a set of views into numpy pictures or a folder. May import capture and everything below."""
