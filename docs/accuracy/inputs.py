"""Reading and validating the three sweeps' JSON files.

Every field the report reads is checked here, once, so that a sweep whose output changed shape
stops the report with the field and the file named, instead of producing an empty table or a
table with holes nobody notices.
"""

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any


class InputError(Exception):
    """An input file is missing, unreadable, or lacks a field the report needs."""


FRAME_TOP_FIELDS = ("benchmark", "quick", "compare_size", "time_size", "renderer", "reference",
                    "scenes", "rows")
FRAME_REFERENCE_FIELDS = ("min_samples", "max_samples", "noise_fraction")
FRAME_SCENE_FIELDS = ("mesh", "world", "lights_found", "order", "images")
FRAME_ROW_FIELDS = ("mesh", "world", "config", "family", "state", "bounce", "surface", "lights",
                    "order", "shadow_resolution", "shadow_filter", "occlusion", "transfer_rays",
                    "transfer_order", "bake_ms", "frame_ms", "shadow_ms", "relative_rms",
                    "fidelity_db", "pixels", "reference_samples", "reference_noise",
                    "reference_mean_luminance", "noise_ratio", "scale_fitted")
# Fields the report does arithmetic on: a null (how nlohmann::json writes NaN and Inf) or a
# non-finite value would otherwise surface as a traceback or a "nan %" cell.
FRAME_ROW_NUMBERS = ("lights", "order", "shadow_resolution", "transfer_rays", "transfer_order",
                     "bake_ms", "frame_ms", "shadow_ms", "relative_rms", "fidelity_db",
                     "reference_mean_luminance", "noise_ratio")
LIGHTING_ROW_NUMBERS = ("order", "downsampling", "projection_ms", "window_ms", "relative_rms",
                        "most_negative")
LIGHTING_TOP_FIELDS = ("benchmark", "quick", "normals", "rows", "worlds")
LIGHTING_ROW_FIELDS = ("world", "subset", "lights_on", "order", "window", "downsampling",
                       "projection_ms", "window_ms", "relative_rms", "max_relative_error",
                       "most_negative")
LIGHTING_WORLD_FIELDS = ("world", "lights", "auto_order")
LOCATION_TOP_FIELDS = ("benchmark", "quick", "cases")
LOCATION_CASE_FIELDS = ("case", "options", "width", "height", "lights_found", "extra_lights",
                        "lights")
LOCATION_LIGHT_FIELDS = ("found",)
# A true light left unmatched has no errors to report; a matched one must have both.
LOCATION_FOUND_LIGHT_FIELDS = ("angular_error_degrees", "intensity_relative_error")


@dataclass
class Sweeps:
    """The three sweeps as read, with where the frame sweep's images live."""

    lighting: dict[str, Any]
    location: dict[str, Any]
    frames: dict[str, Any]
    frames_dir: Path
    lighting_path: Path
    location_path: Path


def read_json(path: Path) -> dict[str, Any]:
    """The JSON object in `path`; a missing or malformed file is an InputError naming it."""
    try:
        with path.open(encoding="utf-8") as file:
            document = json.load(file)
    except OSError as error:
        raise InputError(f"{path}: cannot read: {error.strerror}") from error
    except json.JSONDecodeError as error:
        raise InputError(f"{path}: not JSON: {error}") from error
    if not isinstance(document, dict):
        raise InputError(f"{path}: expected a JSON object at the top")
    return document


def require_fields(record: Any, fields: tuple[str, ...], where: str, path: Path) -> None:
    """Raises an InputError naming the first of `fields` that `record` lacks."""
    if not isinstance(record, dict):
        raise InputError(f"{path}: {where}: expected an object")
    for field in fields:
        if field not in record:
            raise InputError(f"{path}: {where}: missing field '{field}'")


def require_numbers(record: dict[str, Any], fields: tuple[str, ...], where: str,
                    path: Path) -> None:
    """Raises an InputError naming the first of `fields` that is not a finite number."""
    for field in fields:
        value = record[field]
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise InputError(f"{path}: {where}: field '{field}' is {json.dumps(value)}, "
                             "expected a finite number")


def require_list(record: dict[str, Any], field: str, path: Path) -> list[Any]:
    """record[field] as a non-empty list: an empty sweep would make every table empty."""
    value = record[field]
    if not isinstance(value, list) or not value:
        raise InputError(f"{path}: field '{field}' must be a non-empty list")
    return value


def require_benchmark(document: dict[str, Any], name: str, path: Path) -> None:
    """Guards against passing one sweep's file in place of another's."""
    if document["benchmark"] != name:
        raise InputError(f"{path}: field 'benchmark' is '{document['benchmark']}', "
                         f"expected '{name}'")


def validate_lighting(document: dict[str, Any], path: Path) -> None:
    """Checks the fields of lighting_sweep's JSON that the report reads."""
    require_fields(document, LIGHTING_TOP_FIELDS, "top level", path)
    require_benchmark(document, "lighting_sweep", path)
    for index, row in enumerate(require_list(document, "rows", path)):
        require_fields(row, LIGHTING_ROW_FIELDS, f"rows[{index}]", path)
        require_numbers(row, LIGHTING_ROW_NUMBERS, f"rows[{index}]", path)
    for index, world in enumerate(require_list(document, "worlds", path)):
        require_fields(world, LIGHTING_WORLD_FIELDS, f"worlds[{index}]", path)


def validate_location(document: dict[str, Any], path: Path) -> None:
    """Checks the fields of light_location_sweep's JSON that the report reads."""
    require_fields(document, LOCATION_TOP_FIELDS, "top level", path)
    require_benchmark(document, "light_location_sweep", path)
    for index, case in enumerate(require_list(document, "cases", path)):
        require_fields(case, LOCATION_CASE_FIELDS, f"cases[{index}]", path)
        for light_index, light in enumerate(case["lights"]):
            where = f"cases[{index}].lights[{light_index}]"
            require_fields(light, LOCATION_LIGHT_FIELDS, where, path)
            if light["found"]:
                require_fields(light, LOCATION_FOUND_LIGHT_FIELDS, where, path)


def validate_frames(document: dict[str, Any], path: Path) -> None:
    """Checks frame_sweep's JSON, and that every image it names exists beside it."""
    require_fields(document, FRAME_TOP_FIELDS, "top level", path)
    require_benchmark(document, "frame_sweep", path)
    require_fields(document["reference"], FRAME_REFERENCE_FIELDS, "reference", path)
    for index, scene in enumerate(require_list(document, "scenes", path)):
        require_fields(scene, FRAME_SCENE_FIELDS, f"scenes[{index}]", path)
        for key, relative in scene["images"].items():
            if not (path.parent / relative).is_file():
                raise InputError(f"{path}: scenes[{index}].images.{key}: no file "
                                 f"{path.parent / relative}")
    for index, row in enumerate(require_list(document, "rows", path)):
        require_fields(row, FRAME_ROW_FIELDS, f"rows[{index}]", path)
        require_numbers(row, FRAME_ROW_NUMBERS, f"rows[{index}]", path)


def read_sweeps(lighting_path: Path, location_path: Path, frames_dir: Path) -> Sweeps:
    """Reads and validates the three sweeps; raises InputError on the first problem."""
    lighting = read_json(lighting_path)
    validate_lighting(lighting, lighting_path)
    location = read_json(location_path)
    validate_location(location, location_path)
    frames_path = frames_dir / "frame_sweep.json"
    frames = read_json(frames_path)
    validate_frames(frames, frames_path)
    return Sweeps(lighting, location, frames, frames_dir, lighting_path, location_path)
