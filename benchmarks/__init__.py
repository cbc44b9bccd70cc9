"""Developer tools that measure the engine (docs/BENCHMARKS.md says which question each answers); they are not part
of the Blender extension (blender_manifest.toml leaves this folder out)."""
