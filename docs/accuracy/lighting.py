"""The lighting and light-location sweeps' tables (sweeps 1 and 3)."""

from typing import Any

from common import MISSING, dominator, markdown_table, milliseconds, percent, signed_percent

Row = dict[str, Any]
WINDOWS = ("none", "hanning", "lanczos", "auto")
DOWNSAMPLINGS = (1, 2, 4, 8)


class LightingRows:
    """The lighting sweep's rows grouped by (world, order, window, downsampling)."""

    def __init__(self, document: dict[str, Any]) -> None:
        self.worlds = {world["world"]: world for world in document["worlds"]}
        self.groups: dict[tuple[str, int, str, int], list[Row]] = {}
        for row in document["rows"]:
            key = (row["world"], row["order"], row["window"], row["downsampling"])
            self.groups.setdefault(key, []).append(row)

    def orders(self) -> list[int]:
        """Every order the sweep ran, ascending."""
        return sorted({order for _, order, _, _ in self.groups})

    def subsets(self, world: str, order: int, window: str = "none",
                downsampling: int = 1) -> list[Row]:
        """The rows of every on/off subset of one setting (empty when it was not run)."""
        return self.groups.get((world, order, window, downsampling), [])

    def whole_map(self, world: str, order: int, window: str = "none",
                  downsampling: int = 1) -> Row | None:
        """The row with every light on, the map as loaded."""
        return next((row for row in self.subsets(world, order, window, downsampling)
                     if all(row["lights_on"])), None)

    def worst(self, world: str, order: int, window: str = "none",
              downsampling: int = 1) -> Row | None:
        """The subset with the largest relative RMS: what a user switching lights can meet."""
        rows = self.subsets(world, order, window, downsampling)
        return max(rows, key=lambda row: row["relative_rms"]) if rows else None

    def settings(self, world: str) -> list[tuple[float, float, tuple[int, str, int]]]:
        """Every (time, worst-subset error, setting) of one world; time is the projection of the
        map and its light masks plus the window's choice, as the sweep's own front counts it."""
        points = []
        for (name, order, window, downsampling), rows in self.groups.items():
            if name == world:
                worst = max(rows, key=lambda row: row["relative_rms"])
                points.append((worst["projection_ms"] + worst["window_ms"],
                               worst["relative_rms"], (order, window, downsampling)))
        return points

    def auto_order_verdict(self, world: str) -> str:
        """Whether the auto order (window none, full resolution, the defaults) is on the front."""
        auto = (self.worlds[world]["auto_order"], "none", 1)
        points = self.settings(world)
        point = next((point for point in points if point[2] == auto), None)
        if point is None:
            return MISSING
        better = dominator(point, points, lambda p: p[0], lambda p: p[1])
        if better is None:
            return f"on the front (order {auto[0]})"
        order, window, downsampling = better[2]
        return (f"no: order {order}, {window}, 1/{downsampling} "
                f"({milliseconds(better[0])} ms, {percent(better[1], 2)})")


def cell(whole: Row | None, worst: Row | None) -> str:
    """"whole / worst subset" relative RMS."""
    if whole is None or worst is None:
        return MISSING
    return f"{percent(whole['relative_rms'], 2)} / {percent(worst['relative_rms'], 2)}"


def order_table(lighting: LightingRows) -> str:
    """Per world, relative RMS by order, window none, full resolution; the auto order bold."""
    orders = lighting.orders()
    rows = []
    for world, info in lighting.worlds.items():
        cells = [cell(lighting.whole_map(world, order), lighting.worst(world, order))
                 for order in orders]
        cells = [f"**{text}**" if order == info["auto_order"] and text != MISSING else text
                 for order, text in zip(orders, cells)]
        rows.append([world, str(info["lights"]), str(info["auto_order"]), *cells])
    return markdown_table(["world", "lights", "auto order", *[f"order {o}" for o in orders]], rows)


def window_table(lighting: LightingRows) -> str:
    """At the auto order: each window's worst-subset error and most negative irradiance."""
    rows = []
    for world, info in lighting.worlds.items():
        cells = []
        for window in WINDOWS:
            rows_run = lighting.subsets(world, info["auto_order"], window)
            worst = lighting.worst(world, info["auto_order"], window)
            cells.append(MISSING if worst is None else
                         f"{percent(worst['relative_rms'], 2)}, "
                         f"{percent(min(r['most_negative'] for r in rows_run), 2)}")
        rows.append([world, str(info["auto_order"]), *cells])
    return markdown_table(["world", "order", *WINDOWS], rows)


def downsampling_table(lighting: LightingRows) -> str:
    """At the auto order, window none: whole-map and worst-subset error, and projection time."""
    rows = []
    for world, info in lighting.worlds.items():
        cells = []
        for factor in DOWNSAMPLINGS:
            whole = lighting.whole_map(world, info["auto_order"], "none", factor)
            worst = lighting.worst(world, info["auto_order"], "none", factor)
            cells.append(MISSING if whole is None or worst is None else
                         f"{cell(whole, worst)}, {milliseconds(whole['projection_ms'])} ms")
        rows.append([world, str(info["auto_order"]), *cells])
    return markdown_table(["world", "order", *[f"1/{f}" for f in DOWNSAMPLINGS]], rows)


def light_summary(light: Row) -> str:
    """One true light: how far its found light is, in angle and intensity."""
    if not light["found"]:
        return "not found"
    return (f"{light['angular_error_degrees']:.2f}°, "
            f"{signed_percent(light['intensity_relative_error'])}")


def location_table(location: dict[str, Any]) -> str:
    """Per case, options and size: lights found and each true light's errors."""
    rows = [[case["case"], case["options"], f"{case['width']}x{case['height']}",
             f"{case['lights_found']} for {len(case['lights'])}", str(case["extra_lights"]),
             "; ".join(light_summary(light) for light in case["lights"])]
            for case in location["cases"]]
    return markdown_table(["case", "options", "map", "found", "extra",
                           "angle, intensity error per true light"], rows)
