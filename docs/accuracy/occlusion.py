"""The tables: the occlusion of the residual map (our default) against plain SH and OER
without it, per mesh, world and bounce mode, and the check of the rule that sizes the transfer
(its ray count and evaluation order) on the bunny."""

from common import MISSING, NOISE_RATIO_LIMIT, markdown_table, milliseconds, minus, percent, value_range
from frames import (DEFAULT, HEADLINE_MESH, NO_OCCLUSION, NOISE_MARK, PLAIN_SH, FrameRows, Row,
                    noisy)

# The target: ours at most this share of plain SH's error, on the product and on the
# ground near it, in both modes.
TARGET_RATIO = 0.5
# The cost target: the bunny's bake with one bounce, on 2 cores (bench/support/targets.hpp).
BAKE_TARGET_MS = 2000.0
MODES = (("none", "none (direct reference)"), ("one", "one (one-bounce reference)"))
ISSUE_SURFACES = (("object", "product"), ("ground near", "ground near"))
RULE_FAMILY = "transfer"
# The rule's ray count is at the knee when it is the fewest rays whose error is within this
# share of the best of the checked ray counts, in every world, mode and surface: further rays
# buy less than this, fewer lose more.
KNEE_TOLERANCE = 0.05


def error_text(row: Row | None) -> str:
    """"13.1 %", marked when the reference's noise is too large a part of it."""
    if row is None:
        return MISSING
    return percent(row["relative_rms"]) + (f" {NOISE_MARK}" if noisy(row) else "")


def ratio(ours: Row | None, plain: Row | None) -> float | None:
    """Our error over plain SH's, None when either is missing."""
    if ours is None or plain is None:
        return None
    return ours["relative_rms"] / plain["relative_rms"]


def verdict(value: float | None) -> str:
    """Whether the target holds for one ratio."""
    if value is None:
        return MISSING
    return "pass" if value <= TARGET_RATIO else "fail"


def occlusion_table(frames: FrameRows) -> str:
    """Per mesh, world and mode: product and ground-near errors of ours, plain SH and OER, the
    ratio ours/plain with its verdict, the bake and the frame times."""
    header = ["mesh", "world", "mode"]
    for _, label in ISSUE_SURFACES:
        header += [f"{label}: ours", "plain SH", "OER", "ours/plain", f"≤ {TARGET_RATIO}"]
    header += ["bake ms", "frame ms, ours / OER"]
    rows = []
    for mesh in frames.meshes():
        for world in frames.worlds(mesh):
            for bounce, mode in MODES:
                ours_object = frames.find(mesh, world, DEFAULT, bounce, "object")
                if ours_object is None:
                    continue
                line = [mesh, world, mode]
                for surface, _ in ISSUE_SURFACES:
                    ours, plain, oer = (frames.find(mesh, world, config, bounce, surface)
                                        for config in (DEFAULT, PLAIN_SH, NO_OCCLUSION))
                    value = ratio(ours, plain)
                    line += [error_text(ours), error_text(plain), error_text(oer),
                             MISSING if value is None else f"{value:.2f}", verdict(value)]
                oer_object = frames.find(mesh, world, NO_OCCLUSION, bounce, "object")
                line += [f"{ours_object['bake_ms']:.0f}",
                         milliseconds(ours_object["frame_ms"]) + " / "
                         + (milliseconds(oer_object["frame_ms"]) if oer_object else MISSING)]
                rows.append(line)
    return markdown_table(header, rows)


def occlusion_summary(frames: FrameRows) -> str:
    """How many comparisons meet the target, the bake and the frame cost."""
    counts = []
    for surface, label in (("object", "product"), ("ground near", "ground near it")):
        ratios = [value for mesh in frames.meshes() for world in frames.worlds(mesh)
                  for bounce, _ in MODES
                  if (value := ratio(frames.find(mesh, world, DEFAULT, bounce, surface),
                                     frames.find(mesh, world, PLAIN_SH, bounce, surface)))
                  is not None]
        if ratios:
            met = sum(value <= TARGET_RATIO for value in ratios)
            counts.append(f"on the {label} in {met} of {len(ratios)} comparisons (ours/plain "
                          f"{value_range(ratios, lambda v: f'{v:.2f}')})")
    text = (f"The target, ours at most {TARGET_RATIO} of plain SH's error, holds "
            + " and ".join(counts) + ".")
    bakes = {row["bounce"]: row["bake_ms"] for row in frames.rows
             if row["mesh"] == HEADLINE_MESH and row["config"] == DEFAULT}
    if "one" in bakes:
        within = "within" if bakes["one"] <= BAKE_TARGET_MS else "above"
        text += (f" The {HEADLINE_MESH}'s transfer bakes in {bakes['one']:.0f} ms with one bounce"
                 + (f" and {bakes['none']:.0f} ms without" if "none" in bakes else "")
                 + f", {within} the target's {BAKE_TARGET_MS:.0f} ms (wall time of every core, "
                 "on a machine that may be shared).")
    costs = [ours["frame_ms"] / oer["frame_ms"] for mesh in frames.meshes()
             for world in frames.worlds(mesh) for bounce, _ in MODES
             if (ours := frames.find(mesh, world, DEFAULT, bounce, "object"))
             and (oer := frames.find(mesh, world, NO_OCCLUSION, bounce, "object"))]
    if costs:
        text += (f" A frame with occlusion takes {value_range(costs, lambda v: f'{v:.2f}')}x "
                 "the time of one without (the whole frame, not the colour pass alone).")
    return text


def rule_points(frames: FrameRows, world: str, bounce: str, surface: str) -> list[Row]:
    """The bunny's rows of the rule's check in one world: the default (the rule's choice) and
    the transfer family's variations of its ray count and evaluation order."""
    return [row for row in frames.configs(HEADLINE_MESH, world, bounce, surface)
            if row["family"] == RULE_FAMILY or row["config"] == DEFAULT]


def rule_worlds(frames: FrameRows) -> list[str]:
    """The worlds the rule's check ran in (the transfer family is there)."""
    return [world for world in frames.worlds(HEADLINE_MESH)
            if any(row["family"] == RULE_FAMILY
                   for row in frames.configs(HEADLINE_MESH, world, "none", "object"))]


def order_label(row: Row) -> str:
    """"order 5", with the rig's order when the transfer is evaluated at a lower one
    (transfer_order is the rig's, at most kTransferBakeOrder)."""
    label = f"order {row['transfer_order']}"
    if row["order"] != row["transfer_order"]:
        label += f" (rig order {row['order']})"
    return label


def transfer_label(row: Row) -> str:
    """"144 rays, order 5"."""
    return f"{row['transfer_rays']} rays, {order_label(row)}"


def is_order_variant(row: Row, default: Row) -> bool:
    """Whether a row of the rule's check varies the order (through the rig), not the rays."""
    return row["config"] != DEFAULT and row["transfer_rays"] == default["transfer_rays"]


def repeats_the_rule(row: Row, default: Row) -> bool:
    """Whether an order variation sets the rig to the order the rule chose anyway (the same
    frame as the default's: left out of the table and the reading)."""
    return is_order_variant(row, default) and row["order"] == default["order"]


def ray_points(frames: FrameRows, world: str, bounce: str, surface: str) -> list[Row]:
    """The ray-count variations at the rule's orders, and the default, by rays."""
    default = frames.find(HEADLINE_MESH, world, DEFAULT, bounce, surface)
    if default is None:
        return []
    return sorted((row for row in rule_points(frames, world, bounce, surface)
                   if not is_order_variant(row, default)), key=lambda row: row["transfer_rays"])


def rule_table(frames: FrameRows) -> str | None:
    """Per world of the check: each ray count and order, its bake times and errors; the rule's
    choice (the default) in bold."""
    header = ["world", "transfer", "bake ms, none / one", "product, none", "product, one",
              "ground near, none", "ground near, one", "frame ms"]
    rows = []
    for world in rule_worlds(frames):
        default = frames.find(HEADLINE_MESH, world, DEFAULT, "none", "object")
        # The ray counts at the rule's orders first, then the other orders.
        points = sorted(rule_points(frames, world, "none", "object"),
                        key=lambda row: (is_order_variant(row, default), row["order"],
                                         row["transfer_rays"]))
        for none_object in points:
            if repeats_the_rule(none_object, default):
                continue
            config = none_object["config"]
            found = {(bounce, surface): frames.find(HEADLINE_MESH, world, config, bounce, surface)
                     for bounce in ("none", "one") for surface in ("object", "ground near")}
            one_object = found[("one", "object")]
            label = transfer_label(none_object)
            if config == DEFAULT:
                label = f"**{label}: the rule**"
            rows.append([world, label,
                         f"{none_object['bake_ms']:.0f} / "
                         + (f"{one_object['bake_ms']:.0f}" if one_object else MISSING),
                         *[error_text(found[key]) for key in
                           (("none", "object"), ("one", "object"), ("none", "ground near"),
                            ("one", "ground near"))],
                         milliseconds(none_object["frame_ms"])])
    return markdown_table(header, rows) if rows else None


def knee_paragraph(frames: FrameRows) -> str | None:
    """Whether the rule's ray count sits at the knee of error against bake time, and what the
    evaluation order changes; None when the check did not run."""
    knees, below, above, order_changes = [], [], [], []
    rule_rays = set()
    bake_growth = []
    for world in rule_worlds(frames):
        for bounce, _ in MODES:
            for surface, _ in ISSUE_SURFACES:
                points = ray_points(frames, world, bounce, surface)
                default = frames.find(HEADLINE_MESH, world, DEFAULT, bounce, surface)
                if len(points) < 2 or default is None:
                    continue
                rule_rays.add(default["transfer_rays"])
                best = min(row["relative_rms"] for row in points)
                knees.append(next(row["transfer_rays"] for row in points
                                  if row["relative_rms"] <= best * (1.0 + KNEE_TOLERANCE)))
                fewer = [row for row in points if row["transfer_rays"] < default["transfer_rays"]]
                more = [row for row in points if row["transfer_rays"] > default["transfer_rays"]]
                if fewer:
                    below.append(fewer[0]["relative_rms"] - default["relative_rms"])
                if more:
                    above.append(default["relative_rms"] - more[-1]["relative_rms"])
                    bake_growth.append(more[-1]["bake_ms"] / default["bake_ms"])
                for row in rule_points(frames, world, bounce, surface):
                    if is_order_variant(row, default) and not repeats_the_rule(row, default):
                        order_changes.append((row["order"], default["order"],
                                              row["relative_rms"] - default["relative_rms"]))
    if not knees or len(rule_rays) != 1:
        return None
    rays = rule_rays.pop()
    knee = max(knees)
    if knee == rays:
        finding = "sits at the knee"
    elif knee < rays:
        finding = f"is past the knee ({knee} rays already come within it)"
    else:
        finding = f"is before the knee (it takes {knee} rays to come within it)"
    text = (f"**Is the rule's choice at the knee?** The rule gives the {HEADLINE_MESH} {rays} "
            f"rays per point. Taking the knee as the fewest rays whose error is within "
            f"{percent(KNEE_TOLERANCE, 0)} of the best of the checked ray counts on the product "
            f"and on the ground near it, in both modes and every world checked, the rule's "
            f"choice {finding}.")
    if below:
        text += f" Fewer rays change the error by {points_range(below)} (positive: worse)"
    if above:
        text += (f"; the most rays checked improve it by {points_range(above)} at "
                 f"{value_range(bake_growth, lambda v: f'{v:.1f}')}x the bake time")
    text += "."
    for order in sorted({change[0] for change in order_changes}):
        changes = [(own, delta) for other, own, delta in order_changes if other == order]
        text += (f" With the rig at order {order} instead of its own "
                 f"({value_range((own for own, _ in changes), str)}; the transfer is evaluated "
                 f"at the rig's order, at most the bake's, `kTransferBakeOrder`), the error "
                 f"changes by "
                 f"{points_range([delta for _, delta in changes])}.")
    return text


def points_range(deltas: list[float]) -> str:
    """Changes of error in percentage points, signed: "+0.09 to +1.52 points", or one value
    when they agree to the format (two decimals: more rays move the error by tenths)."""
    low, high = (minus(f"{100.0 * delta:+.2f}") for delta in (min(deltas), max(deltas)))
    return f"{low} points" if low == high else f"{low} to {high} points"


def occlusion_section(frames: FrameRows, figure_link: str | None) -> str:
    """The report's occlusion section, first after the header."""
    text = [
        "## Occlusion of the residual map", "",
        "Our default now occludes the residual map (the map minus the lights OER found) through "
        "the scene's baked transfer: soft self-shadows, contact shadows on the ground and, in "
        "the `one` mode, the light the product and the ground reflect once. Each mode is "
        "compared only with the reference of the same mode: `none` (the ground lights nothing) "
        "with the direct reference, `one` (the default) with the one-bounce reference. "
        "\"OER\" is OER without occlusion (`--occlusion off`). Errors: relative RMS of "
        "luminance over the product and over the ground within one bounding-sphere radius of "
        "the product's footprint (\"ground near\"), all lights on; every surface without its "
        "silhouette (a pixel whose four neighbours are not all of its surface measures how a "
        "renderer integrates the pixel, not its light: under the studio lamp behind the bunny's "
        "ears, 96 % of the product's squared error was there), and over the means of 4×4-pixel "
        "blocks inside it, not pixel by pixel (the edges of thin geometry inside a product, the "
        "engine's fins, measure anti-aliasing too; lighting error is of low frequency, and a "
        "block's mean has a quarter of a pixel's reference noise). \"bake ms\": the "
        "transfer's bake in that mode (once per mesh, every world shares it); \"frame ms\": the "
        "whole frame at the time size.", "",
        occlusion_table(frames), "",
        occlusion_summary(frames)]
    table = rule_table(frames)
    if table is not None:
        text += ["", "### The rule is checked: ray count and evaluation order", "",
                 f"The {HEADLINE_MESH}, its transfer baked with other ray counts and evaluated at "
                 "other SH orders (through the rig's order) than the rule's "
                 "(`transfer_ray_count`, `transfer_order`), against the same references.", "",
                 table]
        if figure_link is not None:
            text += ["", f"![the rule's check]({figure_link})"]
        knee = knee_paragraph(frames)
        if knee is not None:
            text += ["", knee]
    if any(noisy(row) for row in frames.rows if row["config"] in (DEFAULT, PLAIN_SH, NO_OCCLUSION)
           and row["state"] == "all on" and row["surface"] in dict(ISSUE_SURFACES)):
        text += ["", f"{NOISE_MARK} the reference's noise is {NOISE_RATIO_LIMIT} of this error or "
                     "more: this comparison does not meet the noise requirement."]
    return "\n".join(text)

