"""The report's "Reading": sentences written from the sweeps' numbers, none typed in by hand.

Each function returns one paragraph, or None when the sweep it reads did not run what it needs
(a --quick sweep has no order 9, for example); the caller says which were left out.
"""

from statistics import mean
from typing import Any

from common import FIDELITY_BOUND_DB, decibels, milliseconds, minus, percent, value_range
from frames import (DEFAULT, HEADLINE_MESH, NO_OCCLUSION, PLAIN_SH, FrameRows, frames_on_front,
                    passes_fidelity)
from lighting import WINDOWS, LightingRows


def points(delta: float, digits: int = 1) -> str:
    """A change in percentage points, signed: "+1.2 points"."""
    return minus(f"{100.0 * delta:+.{digits}f}") + " points"


def sh_truncation(lighting: LightingRows) -> str | None:
    """How much of the irradiance error the SH order leaves, and what the auto order buys."""
    worlds = list(lighting.worlds)
    at_three = [lighting.whole_map(world, 3) for world in worlds]
    worst_three = [lighting.worst(world, 3) for world in worlds]
    autos = [lighting.whole_map(world, info["auto_order"])
             for world, info in lighting.worlds.items()]
    worst_autos = [lighting.worst(world, info["auto_order"])
                   for world, info in lighting.worlds.items()]
    if None in at_three + worst_three + autos + worst_autos:
        return None
    on_front = sum(lighting.auto_order_verdict(world).startswith("on the front")
                   for world in worlds)
    orders = [info["auto_order"] for info in lighting.worlds.values()]
    return (f"**SH truncation.** At order 3 (the thesis's 9 coefficients, no window, the map at "
            f"full resolution) the irradiance error over the sphere is "
            f"{value_range((r['relative_rms'] for r in at_three), percent)} for the whole map "
            f"and up to {percent(max(r['relative_rms'] for r in worst_three))} for the worst "
            f"on/off subset of its lights, over {len(worlds)} worlds. The auto order "
            f"({value_range(orders, str)}) brings it to "
            f"{value_range((r['relative_rms'] for r in autos), lambda v: percent(v, 2))} "
            f"(worst subset up to {percent(max(r['relative_rms'] for r in worst_autos), 2)}), and "
            f"is on the front of projection time against error in {on_front} of {len(worlds)} "
            f"worlds.")


def windows(lighting: LightingRows) -> str | None:
    """What the deringing windows cost in error at the auto order, and the ringing they remove."""
    means = {}
    for window in WINDOWS:
        worst = [lighting.worst(world, info["auto_order"], window)
                 for world, info in lighting.worlds.items()]
        if None in worst:
            return None
        means[window] = mean(row["relative_rms"] for row in worst)
    ringing = {window: min(row["most_negative"] for world, info in lighting.worlds.items()
                           for row in lighting.subsets(world, info["auto_order"], window))
               for window in WINDOWS}
    return ("**Windows.** At the auto order the worst subset's error, averaged over the worlds, "
            "is " + ", ".join(f"{percent(means[w], 2)} with {w}" for w in WINDOWS)
            + "; the most negative irradiance (ringing, as a fraction of the largest true one) is "
            + ", ".join(f"{percent(ringing[w], 2)} with {w}" for w in WINDOWS) + ".")


def downsampling(lighting: LightingRows) -> str | None:
    """What projecting a smaller map costs in error and saves in time."""
    changes, speedups = [], []
    for world, info in lighting.worlds.items():
        full = lighting.whole_map(world, info["auto_order"])
        small = lighting.whole_map(world, info["auto_order"], "none", 4)
        worst_full = lighting.worst(world, info["auto_order"])
        worst_small = lighting.worst(world, info["auto_order"], "none", 4)
        if None in (full, small, worst_full, worst_small):
            return None
        changes.append((abs(small["relative_rms"] - full["relative_rms"]),
                        worst_small["relative_rms"] - worst_full["relative_rms"]))
        speedups.append(full["projection_ms"] / small["projection_ms"])
    return (f"**Map downsampling.** Projecting the map downsampled by 4 moves the whole map's "
            f"error by at most {points(max(c[0] for c in changes), 2).removeprefix('+')} and the "
            f"worst subset's by up to {points(max(c[1] for c in changes))} (its light masks are "
            f"coarser), and projects {value_range(speedups, lambda v: f'{v:.0f}')}x faster.")


def light_location(location: dict[str, Any]) -> str:
    """How well the default light location finds the known lights of the synthetic maps."""
    cases = [case for case in location["cases"] if case["options"] == "default"]
    exact = [case for case in cases if finds_exactly(case)]
    lights = [light for case in exact for light in case["lights"] if light["found"]]
    wrong = sorted({f"{case['case']} ({case['lights_found']} found for {len(case['lights'])})"
                    for case in cases if case not in exact})
    text = (f"**Light location.** With the default options, {len(exact)} of {len(cases)} "
            f"synthetic cases find exactly their lights")
    if lights:
        angle = max(light["angular_error_degrees"] for light in lights)
        intensity = max(abs(light["intensity_relative_error"]) for light in lights)
        text += (f", within {angle:.2f}° of the true direction and {percent(intensity)} of the "
                 "true intensity")
    text += "." if not wrong else f"; not so: {', '.join(wrong)}."
    others = sorted({case["options"] for case in location["cases"]} - {"default"})
    if others:
        text += " Cases found exactly with the other options: " + ", ".join(
            f"{options} {exact_cases(location, options)} of "
            f"{sum(case['options'] == options for case in location['cases'])}"
            for options in others) + "."
    return text


def exact_cases(location: dict[str, Any], options: str) -> int:
    """How many cases with `options` find exactly their lights, none split off or merged."""
    return sum(finds_exactly(case) for case in location["cases"] if case["options"] == options)


def finds_exactly(case: dict[str, Any]) -> bool:
    """Whether a light-location case found as many lights as it painted, none extra."""
    return case["lights_found"] == len(case["lights"]) and case["extra_lights"] == 0


def pipelines(frames: FrameRows) -> str | None:
    """The headline: our default beside OER without occlusion, plain SH and the thesis on the
    bunny."""
    figures = {}
    for config in (DEFAULT, NO_OCCLUSION, PLAIN_SH, "thesis"):
        rows = [row for world in frames.worlds(HEADLINE_MESH)
                if (row := frames.find(HEADLINE_MESH, world, config)) is not None]
        if not rows:
            return None
        figures[config] = rows
    default = figures[DEFAULT]
    passing = sum(passes_fidelity([row]) for row in default)

    def describe(rows: list[dict[str, Any]]) -> str:
        return (f"{value_range((r['relative_rms'] for r in rows), percent)} at "
                f"{value_range((r['frame_ms'] for r in rows), milliseconds)} ms")

    shadows = sorted({(row["shadow_resolution"], row["shadow_filter"]) for row in default})
    settings = (f"{value_range((r['lights'] for r in default), str)} lights (the automatic "
                f"light count), SH order {value_range((r['order'] for r in default), str)} (the "
                "automatic order), "
                + " or ".join(f"{resolution} {name} shadows" for resolution, name in shadows))
    return (f"**The pipelines.** Our default renders with {settings}, and occludes the residual "
            f"map through the scene's transfer. On the {HEADLINE_MESH}'s pixels, against the "
            f"direct reference, our default's error is {describe(default)} over {len(default)} "
            f"worlds; OER's without occlusion {describe(figures[NO_OCCLUSION])}; plain SH's "
            f"{describe(figures[PLAIN_SH])}; the thesis's "
            f"{describe(figures['thesis'])}. Our default's object stays at or below "
            f"model-viewer's {decibels(FIDELITY_BOUND_DB)} dB in {passing} of {len(default)} "
            f"worlds.")


def shadow_resolution(frames: FrameRows) -> str | None:
    """What the shadow-map resolution changes, per filter, from the smallest to the largest."""
    sentences = []
    for shadow_filter in ("hard", "pcf"):
        changes, times = [], []
        resolutions = set()
        for world in frames.worlds(HEADLINE_MESH):
            rows = [row for row in frames.configs(HEADLINE_MESH, world, "none", "object")
                    if row["family"] == "shadows" and row["shadow_filter"] == shadow_filter]
            if len(rows) < 2:
                continue
            low = min(rows, key=lambda row: row["shadow_resolution"])
            high = max(rows, key=lambda row: row["shadow_resolution"])
            resolutions.update((low["shadow_resolution"], high["shadow_resolution"]))
            changes.append(high["relative_rms"] - low["relative_rms"])
            times.append((low["frame_ms"], high["frame_ms"]))
        if changes:
            sentences.append(
                f"with {shadow_filter} shadows, from {min(resolutions)} to {max(resolutions)} "
                f"the object's error changes by {points(min(changes))} to {points(max(changes))} "
                f"(mean {points(mean(changes))}) while the frame goes from "
                f"{milliseconds(mean(t[0] for t in times))} to "
                f"{milliseconds(mean(t[1] for t in times))} ms (means over worlds)")
    if not sentences:
        return None
    return f"**Shadow-map resolution.** On the {HEADLINE_MESH}, " + "; ".join(sentences) + "."


def shadow_filter(frames: FrameRows) -> str | None:
    """What hard shadows in place of OER's soft ones change, at the same resolution (the shadow
    family varies OER without occlusion)."""
    changes: dict[str, list[float]] = {"object": [], "ground": []}
    times = []
    for world in frames.worlds(HEADLINE_MESH):
        for surface, deltas in changes.items():
            default = frames.find(HEADLINE_MESH, world, NO_OCCLUSION, "none", surface)
            if default is None or default["shadow_filter"] != "pcf":
                continue
            hard = frames.find(HEADLINE_MESH, world,
                               f"shadows {default['shadow_resolution']} hard", "none", surface)
            if hard is None:
                continue
            deltas.append(hard["relative_rms"] - default["relative_rms"])
            if surface == "object":
                times.append(hard["frame_ms"] - default["frame_ms"])
    if not changes["object"]:
        return None
    parts = [f"by {points(min(deltas))} to {points(max(deltas))} (mean {points(mean(deltas))}) "
             f"on the {surface}" for surface, deltas in changes.items() if deltas]
    return (f"**Hard against soft shadows.** Hard shadows in place of OER's soft ones (without "
            f"occlusion), at the default's resolution, change the {HEADLINE_MESH}'s error "
            + " and ".join(parts) + f" over {len(changes['object'])} worlds (positive: hard "
            f"shadows are further from the reference), and its frame time by "
            f"{minus(f'{min(times):+.1f}')} to {minus(f'{max(times):+.1f}')} ms.")


def one_bounce(frames: FrameRows) -> str | None:
    """How much further OER without occlusion (which has no bounce) is from a reference that
    adds one diffuse bounce."""
    parts = []
    for surface in ("object", "ground"):
        pairs = [(frames.find(HEADLINE_MESH, world, NO_OCCLUSION, "none", surface),
                  frames.find(HEADLINE_MESH, world, NO_OCCLUSION, "one", surface))
                 for world in frames.worlds(HEADLINE_MESH)]
        pairs = [pair for pair in pairs if None not in pair]
        if pairs:
            direct = value_range((pair[0]["relative_rms"] for pair in pairs), percent)
            bounced = value_range((pair[1]["relative_rms"] for pair in pairs), percent)
            parts.append(f"on the {surface} {bounced} instead of {direct}")
    brighter = []
    for surface in ("object", "ground"):
        ratios = [bounced["reference_mean_luminance"] / direct["reference_mean_luminance"] - 1.0
                  for world in frames.worlds(HEADLINE_MESH)
                  if (direct := frames.find(HEADLINE_MESH, world, NO_OCCLUSION, "none", surface))
                  and (bounced := frames.find(HEADLINE_MESH, world, NO_OCCLUSION, "one", surface))]
        if ratios:
            brighter.append(f"the {surface} {value_range(ratios, percent)}")
    if not parts:
        return None
    return ("**What one bounce adds.** One diffuse bounce makes the reference brighter by "
            + " and ".join(brighter) + ". Against the reference with one diffuse bounce (light OER "
            "without occlusion leaves out), its error is " + ", and ".join(parts) + ".")


def light_count(frames: FrameRows) -> str | None:
    """The error by light count; whether the automatic count and the default are on the front."""
    by_count: dict[int, list[float]] = {}
    chosen = []
    for world in frames.worlds(HEADLINE_MESH):
        for row in frames.configs(HEADLINE_MESH, world, "none", "object"):
            if row["family"] == "lights":
                by_count.setdefault(row["lights"], []).append(row["relative_rms"])
            if row["config"] == NO_OCCLUSION:
                chosen.append(row["lights"])
    if not by_count or not chosen:
        return None
    auto_object, ran = frames_on_front(frames, NO_OCCLUSION, "object", "lights")
    auto_ground, _ = frames_on_front(frames, NO_OCCLUSION, "ground", "lights")
    default_object, default_ran = frames_on_front(frames, DEFAULT, "object")
    default_ground, _ = frames_on_front(frames, DEFAULT, "ground")
    counts = ", ".join(f"{percent(mean(errors))} with {count}"
                       for count, errors in sorted(by_count.items()))
    return (f"**Light count.** The {HEADLINE_MESH}'s object error, averaged over worlds, is "
            f"{counts} lights. The auto light count (the default's) picks "
            f"{value_range(chosen, str)} and lands on the front of the light counts in "
            f"{auto_object} of {ran} worlds for the object and {auto_ground} for "
            f"the ground; the default configuration is on the front of every configuration in {default_object} of "
            f"{default_ran} worlds for the object and {default_ground} for the ground.")


def paragraphs(lighting: LightingRows, location: dict[str, Any],
               frames: FrameRows) -> tuple[list[str], list[str]]:
    """The reading's paragraphs, and the names of those the inputs could not support."""
    writers = {"pipelines": lambda: pipelines(frames),
               "light count": lambda: light_count(frames),
               "SH truncation": lambda: sh_truncation(lighting),
               "windows": lambda: windows(lighting),
               "downsampling": lambda: downsampling(lighting),
               "light location": lambda: light_location(location),
               "shadow resolution": lambda: shadow_resolution(frames),
               "shadow filter": lambda: shadow_filter(frames),
               "one bounce": lambda: one_bounce(frames)}
    written, skipped = [], []
    for name, write in writers.items():
        text = write()
        (written if text else skipped).append(text or name)
    return written, skipped
