"""Measuring: PSNR/SSIM/identity mIoU (also used by training), LPIPS, FID/KID, the benchmark's masked
scores, and evaluating a trained scene on its test views. May import render, io, formats, base."""
