"""Splat files in and out: a splat trained elsewhere made into a run (`import-splat`), and a run's scene
written as .ply, compressed .ply, .splat or .spz (`export`). May import train and everything below."""
