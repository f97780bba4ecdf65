"""The frame sweep's tables: the occlusion section, the headline, the per-mesh summary, the
front, the rule's check, the images."""

import shutil
from pathlib import Path
from statistics import mean
from typing import Any

from common import (FIDELITY_BOUND_DB, MISSING, NOISE_RATIO_LIMIT, decibels, dominator,
                    markdown_table, milliseconds, percent)
from inputs import InputError

Row = dict[str, Any]
DEFAULT = "default"
# OER without occlusion of the residual map (the thesis's lighting): the baseline of the light
# count, shadow and SH order families, which vary its settings.
NO_OCCLUSION = "OER, no occlusion"
PLAIN_SH = "plain SH"
PIPELINES = ((DEFAULT, "ours (default)"), (NO_OCCLUSION, "OER, no occlusion"),
             (PLAIN_SH, "plain SH"), ("thesis", "thesis"))
HEADLINE_MESH = "bunny"
SURFACES = ("object", "ground", "ground near")
COMPARISONS = tuple((bounce, surface) for bounce in ("none", "one") for surface in SURFACES)
NOISE_MARK = "†"
IMAGE_COLUMNS = (("reference", "reference"), ("reference_one_bounce", "reference + one bounce"),
                 ("default", "ours (default)"), ("default_one_bounce", "ours, one bounce"),
                 ("oer_no_occlusion", "OER, no occlusion"), ("plain_sh", "plain SH"),
                 ("thesis", "thesis"), ("error_default", "error, ours"),
                 ("error_default_one_bounce", "error, ours vs one bounce"),
                 ("error_oer_no_occlusion", "error, OER"), ("error_plain_sh", "error, plain SH"))
IMAGE_WIDTH = 112


class FrameRows:
    """The frame sweep's rows, looked up by what a table asks for."""

    def __init__(self, rows: list[Row]) -> None:
        self.rows = rows
        self.index = {(row["mesh"], row["world"], row["config"], row["state"], row["bounce"],
                       row["surface"]): row for row in rows}

    def find(self, mesh: str, world: str, config: str, bounce: str = "none",
             surface: str = "object", state: str = "all on") -> Row | None:
        """The row of one comparison, or None when the sweep did not run it."""
        return self.index.get((mesh, world, config, state, bounce, surface))

    def meshes(self) -> list[str]:
        """Meshes in the order the sweep ran them."""
        return list(dict.fromkeys(row["mesh"] for row in self.rows))

    def worlds(self, mesh: str) -> list[str]:
        """Worlds of one mesh, in the sweep's order."""
        return list(dict.fromkeys(row["world"] for row in self.rows if row["mesh"] == mesh))

    def configs(self, mesh: str, world: str, bounce: str, surface: str) -> list[Row]:
        """Every configuration of one scene, all lights on, against one reference."""
        return [row for row in self.rows
                if (row["mesh"], row["world"], row["state"], row["bounce"], row["surface"])
                == (mesh, world, "all on", bounce, surface)]


def noisy(row: Row) -> bool:
    """Whether the reference's noise is too large a part of this comparison's error."""
    return row["noise_ratio"] >= NOISE_RATIO_LIMIT


def error_cell(row: Row | None) -> str:
    """"13.1 % / −24.3 dB", marked when the comparison misses the noise requirement."""
    if row is None:
        return MISSING
    mark = f" {NOISE_MARK}" if noisy(row) else ""
    return f"{percent(row['relative_rms'])} / {decibels(row['fidelity_db'])} dB{mark}"


def passes_fidelity(rows: list[Row]) -> bool:
    """model-viewer's criterion, on the object and on the ground against the direct reference."""
    return all(row["fidelity_db"] <= FIDELITY_BOUND_DB for row in rows)


def headline_row(frames: FrameRows, world: str, config: str, name: str) -> list[str] | None:
    """One renderer's line of the headline table, or None when the sweep lacks it."""
    found = [frames.find(HEADLINE_MESH, world, config, bounce, surface)
             for bounce, surface in COMPARISONS]
    present = [row for row in found if row is not None]
    if not present:
        return None
    direct = [row for (bounce, surface), row in zip(COMPARISONS, found)
              if row is not None and bounce == "none" and surface != "ground near"]
    timed = found[0] or present[0]
    verdict = ("passes" if passes_fidelity(direct) else "fails") if direct else MISSING
    noise = max(row["noise_ratio"] for row in present)
    return [world, name, *[error_cell(row) for row in found], milliseconds(timed["frame_ms"]),
            f"{noise:.2f}", verdict]


def headline_table(frames: FrameRows) -> str:
    """Per world, the pipelines against both references (the headline figures)."""
    header = ["world", "renderer",
              *[f"{surface}, {'direct' if bounce == 'none' else 'one bounce'}"
                for bounce, surface in COMPARISONS], "frame ms", "noise/error", "−22 dB"]
    rows = [line for world in frames.worlds(HEADLINE_MESH) for config, name in PIPELINES
            if (line := headline_row(frames, world, config, name)) is not None]
    return markdown_table(header, rows)


def any_noisy(frames: FrameRows) -> bool:
    """Whether any headline comparison misses the noise requirement (the footnote is needed)."""
    return any(noisy(row) for row in frames.rows
               if row["mesh"] == HEADLINE_MESH and row["family"] == "pipeline")


def mean_error(rows: list[Row | None]) -> str:
    """The mean relative RMS of the rows present, or a dash."""
    present = [row["relative_rms"] for row in rows if row is not None]
    return percent(mean(present)) if present else MISSING


def mesh_summary_table(frames: FrameRows) -> str:
    """Per mesh, the pipelines' means over worlds, direct reference, all lights on."""
    header = ["mesh", "renderer", "worlds", "object error", "ground error", "ground near error",
              "object dB", "frame ms", "passes −22 dB"]
    rows = []
    for mesh in frames.meshes():
        for config, name in PIPELINES:
            pairs = [(frames.find(mesh, world, config, "none", "object"),
                      frames.find(mesh, world, config, "none", "ground"))
                     for world in frames.worlds(mesh)]
            pairs = [(obj, ground) for obj, ground in pairs if obj is not None]
            if not pairs:
                continue
            passing = sum(passes_fidelity([obj] + ([ground] if ground else []))
                          for obj, ground in pairs)
            near = [frames.find(mesh, obj["world"], config, "none", "ground near")
                    for obj, _ in pairs]
            rows.append([mesh, name, str(len(pairs)),
                         percent(mean(obj["relative_rms"] for obj, _ in pairs)),
                         mean_error([ground for _, ground in pairs]), mean_error(near),
                         decibels(mean(obj["fidelity_db"] for obj, _ in pairs)),
                         milliseconds(mean(obj["frame_ms"] for obj, _ in pairs)),
                         f"{passing} of {len(pairs)}"])
    return markdown_table(header, rows)


def front_verdict(frames: FrameRows, world: str, config: str, surface: str,
                  family: str | None = None) -> str:
    """Whether one configuration of the bunny is on the world's front, and if not what beats it.

    The front is over the configurations with an absolute scale (a scale-fitted one, the
    thesis's, is compared at its best exposure: no setting a user could choose); with `family`,
    over that family's configurations and `config` only, so that one choice (the light count,
    the shadow maps, the SH order) is judged with everything else as in `config`."""
    points = [row for row in frames.configs(HEADLINE_MESH, world, "none", surface)
              if not row["scale_fitted"]
              and (family is None or row["family"] == family or row["config"] == config)]
    point = next((row for row in points if row["config"] == config), None)
    if point is None:
        return MISSING
    better = dominator(point, points, lambda row: row["frame_ms"], lambda row: row["relative_rms"])
    if better is None:
        return "on the front"
    return (f"no: {better['config']} ({milliseconds(better['frame_ms'])} ms, "
            f"{percent(better['relative_rms'])})")


def frames_on_front(frames: FrameRows, config: str, surface: str,
                    family: str | None = None) -> tuple[int, int]:
    """On how many of the bunny's worlds `config` is on the front, and of how many it ran in."""
    verdicts = [front_verdict(frames, world, config, surface, family)
                for world in frames.worlds(HEADLINE_MESH)]
    ran = [verdict for verdict in verdicts if verdict != MISSING]
    return sum(verdict == "on the front" for verdict in ran), len(ran)


def image_cell(scene: dict[str, Any], key: str, frames_dir: Path, out_images: Path,
               link_prefix: str, copied: dict[str, Path]) -> str:
    """An <img> of one of the scene's images, copied beside the report; a dash when absent.
    `copied` maps the names already copied to their sources: the copies share one folder, so
    two sources of one name would otherwise show one image twice."""
    relative = scene["images"].get(key)
    if relative is None:
        return MISSING
    source = frames_dir / relative
    if copied.setdefault(source.name, source) != source:
        raise InputError(f"{frames_dir / 'frame_sweep.json'}: images {copied[source.name]} and "
                         f"{source} share the name {source.name}")
    shutil.copyfile(source, out_images / source.name)
    return f'<img src="{link_prefix}/{source.name}" width="{IMAGE_WIDTH}">'


def images_table(scenes: list[dict[str, Any]], frames_dir: Path, out_images: Path,
                 link_prefix: str) -> str:
    """Side by side per scene: both references, the three renderers and the error maps."""
    out_images.mkdir(parents=True, exist_ok=True)
    header = ["scene"] + [name for _, name in IMAGE_COLUMNS]
    copied: dict[str, Path] = {}
    rows = [[f"{scene['mesh']}, {scene['world']}"]
            + [image_cell(scene, key, frames_dir, out_images, link_prefix, copied)
               for key, _ in IMAGE_COLUMNS] for scene in scenes]
    return markdown_table(header, rows)
