"""Large files (the FID weights, Ray's wheel) sent to a GPU host in parts, for a copy of the tree that is capped in
size per transfer: split here, joined there.

    python benchmarks/carry.py split FILE... [--mb 30]     # -> .bench/carry-<k>/ (send each folder in its own copy)
    python3 benchmarks/carry.py join DEST                   # on the GPU host: every file whose parts have all come

`split` writes parts of at most --mb MB into numbered folders under .bench/ (git-ignored), each part named
FILE.partK-of-N beside a .sha256 of the whole file. `join` (run by benchmarks/gpu.sh before each job) keeps the parts
that arrived in DEST/.parts and writes a file once all of its parts are there and its checksum holds; a file whose
parts have not all come stays absent, never half written.
"""

from __future__ import annotations

import hashlib
import re
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
PART = re.compile(r"(.+)\.part(\d+)-of-(\d+)")


def split(files: list[Path], mb: int) -> None:
    size = mb * 1_000_000
    folder, used = 0, size  # a new folder for the first part
    for path in files:
        data = path.read_bytes()
        count = max(1, -(-len(data) // size))
        digest = hashlib.sha256(data).hexdigest()
        for k in range(count):
            piece = data[k * size:(k + 1) * size]
            if used + len(piece) > size:
                folder, used = folder + 1, 0
            out = REPO / ".bench" / f"carry-{folder}"
            out.mkdir(parents=True, exist_ok=True)
            (out / f"{path.name}.part{k + 1}-of-{count}").write_bytes(piece)
            (out / f"{path.name}.sha256").write_text(digest)
            used += len(piece)
    for out in sorted((REPO / ".bench").glob("carry-*")):
        print(out.relative_to(REPO), sum(p.stat().st_size for p in out.iterdir()) // 1_000_000, "MB")


def join(dest: Path) -> None:
    parts = dest / ".parts"
    parts.mkdir(parents=True, exist_ok=True)
    for path in (REPO / ".bench").glob("carry-*/*"):
        shutil.copy(path, parts / path.name)
    groups: dict[tuple[str, int], dict[int, Path]] = {}
    for path in parts.iterdir():
        match = PART.fullmatch(path.name)
        if match:
            groups.setdefault((match[1], int(match[3])), {})[int(match[2])] = path
    for (name, count), got in sorted(groups.items()):
        if len(got) < count or (dest / name).exists():
            continue
        data = b"".join(got[k].read_bytes() for k in range(1, count + 1))
        want = (parts / f"{name}.sha256").read_text().strip() if (parts / f"{name}.sha256").exists() else None
        if want != hashlib.sha256(data).hexdigest():
            print(f"{name}: checksum does not match, left out", file=sys.stderr)
            continue
        (dest / f"{name}.tmp").write_bytes(data)
        (dest / f"{name}.tmp").rename(dest / name)
        print(f"joined {name}")


def main() -> int:
    if len(sys.argv) >= 3 and sys.argv[1] == "split":
        args, mb = sys.argv[2:], 30
        if "--mb" in args:
            mb = int(args[args.index("--mb") + 1])
            args = args[:args.index("--mb")] + args[args.index("--mb") + 2:]
        split([Path(a) for a in args], mb)
        return 0
    if len(sys.argv) == 3 and sys.argv[1] == "join":
        join(Path(sys.argv[2]))
        return 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
