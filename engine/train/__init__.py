"""Stage 1, grouping: Gaussian Grouping training on gsplat (one loop with plug-ins), its settings, a run
folder that resumes and cancels, and a finished run read back. May import pictures and everything below."""
