"""The report's figures (matplotlib, Agg): time against error, the Pareto front marked."""

import math
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")  # no display: the report is built headless, in CI too
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

from common import pareto_front  # noqa: E402
from frames import DEFAULT, HEADLINE_MESH, FrameRows  # noqa: E402
from lighting import LightingRows  # noqa: E402
from occlusion import ISSUE_SURFACES, MODES, ray_points, rule_worlds  # noqa: E402

DPI = 100
LABEL_SIZE = 6.5
# Offsets (points) cycled over neighbouring labels so that close points' names do not sit on
# one another; a layout solver would do better, these keep every name readable in practice.
LABEL_OFFSETS = ((4, 4), (4, -9), (-4, 6), (-4, -10), (6, 0), (-6, 0))
FRONT_STYLE = {"color": "tab:red", "linewidth": 1.2, "where": "post"}


def label_points(axes: Any, xs: list[float], ys: list[float], labels: list[str]) -> None:
    """Writes each point's name beside it, with offsets cycled along the x order."""
    order = sorted(range(len(xs)), key=lambda index: (xs[index], ys[index]))
    for rank, index in enumerate(order):
        dx, dy = LABEL_OFFSETS[rank % len(LABEL_OFFSETS)]
        axes.annotate(labels[index], (xs[index], ys[index]), textcoords="offset points",
                      xytext=(dx, dy), fontsize=LABEL_SIZE, ha="left" if dx >= 0 else "right")


def log_if_wide(axes: Any, xs: list[float]) -> None:
    """A log time axis when times span more than a decade, else a linear one that reads easier."""
    positive = [x for x in xs if x > 0]
    if positive and max(positive) / min(positive) > 10:
        axes.set_xscale("log")


def draw_front(axes: Any, points: list[tuple[float, float, str]], highlight: set[str],
               highlight_label: str) -> None:
    """Scatter of (time, error, name), the front as a step line, the `highlight` names starred."""
    xs, ys, names = [p[0] for p in points], [p[1] for p in points], [p[2] for p in points]
    axes.scatter(xs, ys, s=14, color="tab:blue", zorder=2)
    front = pareto_front(points, lambda p: p[0], lambda p: p[1])
    axes.step([p[0] for p in front], [p[1] for p in front], label="Pareto front", **FRONT_STYLE)
    axes.scatter([p[0] for p in front], [p[1] for p in front], s=36, facecolors="none",
                 edgecolors="tab:red", zorder=3)
    marked = [p for p in points if p[2] in highlight]
    axes.scatter([p[0] for p in marked], [p[1] for p in marked], s=60, marker="*",
                 color="tab:orange", zorder=4, label=highlight_label)
    label_points(axes, xs, ys, names)
    log_if_wide(axes, xs)
    axes.margins(x=0.12, y=0.1)  # room for the outermost points' labels
    axes.grid(True, linewidth=0.3)
    axes.legend(fontsize=7, loc="upper right")


def frame_figure(frames: FrameRows, world: str, path: Path) -> None:
    """The bunny under one world: frame time against error, object and ground side by side."""
    figure, panels = plt.subplots(1, 2, figsize=(11, 4.6))
    for axes, surface in zip(panels, ("object", "ground")):
        rows = frames.configs(HEADLINE_MESH, world, "none", surface)
        points = [(row["frame_ms"], 100.0 * row["relative_rms"], row["config"]) for row in rows]
        draw_front(axes, points, {DEFAULT},
                   "default (occlusion, auto lights and order, 2048 pcf)")
        axes.set_title(f"{HEADLINE_MESH}, {world}: {surface} pixels", fontsize=10)
        axes.set_xlabel("frame time at the time size (ms)")
        axes.set_ylabel("relative RMS of luminance vs direct reference (%)")
    figure.tight_layout()
    figure.savefig(path, dpi=DPI)
    plt.close(figure)


def rule_figure(frames: FrameRows, path: Path) -> None:
    """The rule's check: per world of the check and per mode, the bunny's error against the
    bake time over the ray counts at the rule's order, product and ground near, the rule's
    choice starred."""
    worlds = rule_worlds(frames)
    figure, panels = plt.subplots(len(MODES), len(worlds),
                                  figsize=(max(3.6 * len(worlds), 7.0), 6.4), squeeze=False)
    for column, world in enumerate(worlds):
        for row_index, (bounce, mode) in enumerate(MODES):
            axes = panels[row_index][column]
            for surface, label in ISSUE_SURFACES:
                points = ray_points(frames, world, bounce, surface)
                xs = [row["bake_ms"] for row in points]
                ys = [100.0 * row["relative_rms"] for row in points]
                axes.plot(xs, ys, marker="o", markersize=3, linewidth=1, label=label)
                for row, x, y in zip(points, xs, ys):
                    axes.annotate(str(row["transfer_rays"]), (x, y), textcoords="offset points",
                                  xytext=(3, 3), fontsize=LABEL_SIZE)
                    if row["config"] == DEFAULT:
                        axes.scatter([x], [y], s=70, marker="*", color="tab:orange", zorder=4)
            axes.set_title(f"{world}, bounce {mode}", fontsize=8)
            axes.set_xlabel("bake ms", fontsize=8)
            axes.set_ylabel("relative RMS (%)", fontsize=8)
            axes.grid(True, linewidth=0.3)
            axes.legend(fontsize=6)
    figure.suptitle(f"{HEADLINE_MESH}: error against the transfer's bake time\nlabelled by "
                    "rays per point; star: the rule's choice", fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=DPI)
    plt.close(figure)


def lighting_figure(lighting: LightingRows, path: Path) -> None:
    """Per world: projection time against worst-subset irradiance error, window none,
    full resolution, labelled by order, the auto order marked."""
    worlds = list(lighting.worlds)
    columns = min(4, len(worlds))
    rows_count = math.ceil(len(worlds) / columns)
    figure, panels = plt.subplots(rows_count, columns, figsize=(3.4 * columns, 3.1 * rows_count),
                                  squeeze=False)
    for axes, world in zip(panels.flat, worlds):
        points = []
        for order in lighting.orders():
            worst = lighting.worst(world, order)
            if worst is not None:
                points.append((worst["projection_ms"] + worst["window_ms"],
                               100.0 * worst["relative_rms"], str(order)))
        draw_front(axes, points, {str(lighting.worlds[world]["auto_order"])}, "auto order")
        axes.set_yscale("log")
        axes.set_title(world, fontsize=9)
        axes.set_xlabel("projection ms", fontsize=8)
        axes.set_ylabel("worst subset error (%)", fontsize=8)
    for axes in list(panels.flat)[len(worlds):]:
        axes.set_visible(False)
    figure.suptitle("SH order: projection time against irradiance error (window none, 1/1); "
                    "star: the auto order", fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=DPI)
    plt.close(figure)
