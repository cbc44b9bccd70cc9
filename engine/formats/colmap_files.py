"""Reading COLMAP models (binary or text) with numpy alone.

Loading a scene therefore never imports pycolmap (whose 4.2.1 wheel breaks zlib when imported first,
and weighs 38 MB); pycolmap is used only to write models (engine.io.colmap_model.write_model), and the tests
check that both agree. Format: COLMAP's `src/colmap/scene/reconstruction_io.cc` (cameras, images, points3D).
"""

from __future__ import annotations

import functools
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from .checks import check_pixels, unit_quaternion
from .layout import SceneLayout

MODELS = {  # model id: (name, number of parameters)
    0: ("SIMPLE_PINHOLE", 3), 1: ("PINHOLE", 4), 2: ("SIMPLE_RADIAL", 4), 3: ("RADIAL", 5), 4: ("OPENCV", 8),
    5: ("OPENCV_FISHEYE", 8), 6: ("FULL_OPENCV", 12), 7: ("FOV", 5), 8: ("SIMPLE_RADIAL_FISHEYE", 4),
    9: ("RADIAL_FISHEYE", 5), 10: ("THIN_PRISM_FISHEYE", 12), 11: ("RAD_TAN_THIN_PRISM_FISHEYE", 16),
}
PARAM_COUNTS = {name: count for name, count in MODELS.values()}
ONE_FOCAL = ("SIMPLE_PINHOLE", "SIMPLE_RADIAL", "RADIAL", "SIMPLE_RADIAL_FISHEYE", "RADIAL_FISHEYE")


@dataclass
class RawCamera:
    model: str
    width: int
    height: int
    params: np.ndarray


@dataclass
class RawImage:
    name: str
    camera_id: int
    qvec: np.ndarray  # (4,) w, x, y, z: world-to-camera rotation
    tvec: np.ndarray  # (3,) world-to-camera translation


class _Reader:
    """Sequential little-endian reads with a clear error at the end of the data."""

    def __init__(self, path: Path) -> None:
        self.path, self.data, self.pos = path, path.read_bytes(), 0

    def read(self, fmt: str) -> tuple:
        size = struct.calcsize("<" + fmt)
        if self.pos + size > len(self.data):
            raise InputError(f"{self.path} is truncated (ends at byte {len(self.data)}); re-export the COLMAP model")
        values = struct.unpack_from("<" + fmt, self.data, self.pos)
        self.pos += size
        return values

    def read_string(self) -> str:
        end = self.data.find(b"\0", self.pos)
        if end < 0:
            raise InputError(f"{self.path} is truncated inside an image name; re-export the COLMAP model")
        text = self.data[self.pos:end].decode("utf-8", errors="replace")
        self.pos = end + 1
        return text

    def count(self, record_bytes: int, what: str) -> int:
        """A record count read from the file, checked against the bytes left (at least `record_bytes` a
        record): a corrupt count must not start a loop of billions of reads."""
        count = self.read("Q")[0]
        if count * record_bytes > len(self.data) - self.pos:
            raise InputError(f"{self.path} declares {count:,} {what} but holds {len(self.data) - self.pos:,} bytes "
                             "more; it is truncated or corrupt, re-export the COLMAP model")
        return count

    def skip(self, nbytes: int) -> None:
        if self.pos + nbytes > len(self.data):
            raise InputError(f"{self.path} is truncated; re-export the COLMAP model")
        self.pos += nbytes


def _parsed(read):
    """A reader whose unreadable file or malformed numbers and fields end in one InputError naming the file."""
    @functools.wraps(read)
    def wrapper(path: Path):
        try:
            return read(path)
        except OSError as exc:
            raise InputError(f"cannot read {path} ({exc.strerror}); check the path or re-export the model") from exc
        except (ValueError, IndexError, OverflowError, UnicodeDecodeError, struct.error) as exc:
            raise InputError(f"cannot parse {path} ({str(exc)[:100]}); re-export the COLMAP model") from exc
    return wrapper


@_parsed
def read_cameras(path: Path) -> dict[int, RawCamera]:
    """Cameras by id, each with a known model, its parameter count, a size within the pixel limit and
    finite parameters whose focal lengths are positive."""
    cameras = {}
    if path.suffix == ".txt":
        for fields in _text_records(path):
            _need(fields, 4, path, "CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]")
            cameras[int(fields[0])] = RawCamera(fields[1], int(fields[2]), int(fields[3]),
                                                np.array(fields[4:], dtype=np.float64))
    else:
        r = _Reader(path)
        for _ in range(r.count(24, "cameras")):
            camera_id, model_id, width, height = r.read("iiQQ")
            if model_id not in MODELS:
                raise InputError(f"{path}: unknown camera model id {model_id}; the file is corrupt")
            name, count = MODELS[model_id]
            cameras[camera_id] = RawCamera(name, width, height, np.array(r.read(f"{count}d")))
    for camera_id, camera in cameras.items():
        _check_camera(camera, camera_id, path)
    return cameras


def _check_camera(camera: RawCamera, camera_id: int, path: Path) -> None:
    where = f"camera {camera_id}"
    if camera.model in PARAM_COUNTS and len(camera.params) != PARAM_COUNTS[camera.model]:
        raise InputError(f"{path}: {where} has {len(camera.params)} parameters for {camera.model}; the model "
                         "is corrupt")
    check_pixels(camera.width, camera.height, f"{path} ({where})")
    if not np.isfinite(camera.params).all():
        raise InputError(f"{path}: {where} has non-finite parameters; the model is corrupt")
    focal = camera.params[:1] if camera.model in ONE_FOCAL else camera.params[:2]
    if len(camera.params) and (focal <= 0).any():
        raise InputError(f"{path}: {where} has focal length {focal.tolist()}, not positive; the model is corrupt")


@_parsed
def read_images(path: Path) -> dict[int, RawImage]:
    images = {}
    if path.suffix == ".txt":
        records = _text_records(path, keep_empty=True)
        for fields in records[0::2]:  # every other line lists the image's 2D points
            _need(fields, 10, path, "IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME")
            images[int(fields[0])] = RawImage(fields[9], int(fields[8]), np.array(fields[1:5], dtype=np.float64),
                                              np.array(fields[5:8], dtype=np.float64))
    else:
        r = _Reader(path)
        for _ in range(r.count(73, "images")):
            image_id, qw, qx, qy, qz, tx, ty, tz, camera_id = r.read("idddddddi")
            name = r.read_string()
            r.skip(24 * r.read("Q")[0])  # points2D: x, y (double) and point3D id (int64)
            images[image_id] = RawImage(name, camera_id, np.array([qw, qx, qy, qz]), np.array([tx, ty, tz]))
    for image in images.values():
        image.qvec = unit_quaternion(image.qvec, path, f"image {image.name}")
        if not np.isfinite(image.tvec).all():
            raise InputError(f"{path}: image {image.name} has a non-finite translation; the model is corrupt")
    return images


@_parsed
def read_points(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) float64 positions and (N, 3) uint8 colours, ordered by point id."""
    rows: list[tuple[int, tuple, tuple]] = []
    if path.suffix == ".txt":
        for fields in _text_records(path):
            _need(fields, 7, path, "POINT3D_ID X Y Z R G B")
            rows.append((int(fields[0]), tuple(map(float, fields[1:4])), tuple(map(int, fields[4:7]))))
    else:
        r = _Reader(path)
        for _ in range(r.count(51, "points")):
            point_id, x, y, z, red, green, blue, _error, track = r.read("QdddBBBdQ")
            r.skip(8 * track)  # (image id, point2D index) int32 pairs
            rows.append((point_id, (x, y, z), (red, green, blue)))
    rows.sort(key=lambda row: row[0])
    xyz = np.array([row[1] for row in rows], dtype=np.float64).reshape(-1, 3)
    rgb = np.array([row[2] for row in rows], dtype=np.int64).reshape(-1, 3)
    if not np.isfinite(xyz).all():
        raise InputError(f"{path} holds points at infinity or NaN; the model is corrupt, re-export it")
    if rgb.size and (rgb.min() < 0 or rgb.max() > 255):
        raise InputError(f"{path} holds colours outside 0..255; the model is corrupt, re-export it")
    return xyz, rgb.astype(np.uint8)


def _need(fields: list[str], count: int, path: Path, layout: str) -> None:
    if len(fields) < count:
        raise InputError(f"{path}: a line has {len(fields)} fields where COLMAP writes {layout}; fix the model")


def _text_records(path: Path, keep_empty: bool = False) -> list[list[str]]:
    lines = path.read_text(errors="replace").splitlines()
    records = [line.split() for line in lines if not line.startswith("#") and (keep_empty or line.strip())]
    return records


def model_ext(model_dir: Path) -> str:
    """".bin" for a binary COLMAP model (cameras.bin present), else ".txt"."""
    return ".bin" if (model_dir / "cameras.bin").is_file() else ".txt"


def find_model_dir(scene_root: Path) -> Path:
    """The folder holding a scene's model: `sparse/0/` (COLMAP's layout) or `sparse/`."""
    sparse = SceneLayout(scene_root).sparse
    for candidate in (sparse / "0", sparse):
        if any((candidate / f"cameras{ext}").is_file() for ext in (".bin", ".txt")):
            return candidate
    raise InputError(
        f"no COLMAP model in {sparse}: expected sparse/0/cameras.bin (or .txt); "
        "run COLMAP (and image_undistorter) on the images first"
    )


def world_to_camera_rotations(scene_root: Path) -> np.ndarray:
    """(K, 3, 3) the world-to-camera rotations of a scene's views (for Blender-side code, which reads no
    more of a model than this)."""
    model_dir = find_model_dir(scene_root)
    images = read_images(model_dir / f"images{model_ext(model_dir)}")
    return np.array([quat_to_rotation(image.qvec) for image in images.values()]).reshape(-1, 3, 3)


def quat_to_rotation(q: np.ndarray) -> np.ndarray:
    """(3, 3) rotation from a unit quaternion w, x, y, z."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
