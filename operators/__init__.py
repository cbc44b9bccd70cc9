"""Thin operators: read properties, call one function, report. The work happens in the engine."""

from __future__ import annotations


def register() -> None:
    from . import check_engine

    check_engine.register()


def unregister() -> None:
    from . import check_engine

    check_engine.unregister()
