"""The Soft shadows section: bench/shadow_sweep's figures, before the Vogel-spiral filter
(docs/accuracy/soft_shadows_before.json, measured on the 16-point Poisson disc) and now."""
from typing import Any

from common import markdown_table, percent

# Below this the reference's high-pass, less its noise's, is not known well enough to divide by
# (shadow_sweep.cpp's kLeastReferenceHighPass).
LEAST_REFERENCE_HIGH_PASS = 0.005


def smoothness(row: dict[str, Any]) -> str:
    """Our high-pass RMS over the reference's (less its noise), or ours alone beside '—'."""
    ours = row["high_pass"]
    reference = row["reference_high_pass"]
    if reference < LEAST_REFERENCE_HIGH_PASS:
        return f"{ours:.4f} / —"
    return f"{ours:.4f} / {reference:.4f} = {ours / reference:.2f}"


def key(row: dict[str, Any]) -> tuple:
    return (row["kind"], row["mesh"], row["world"], row["light"], row["shadow_resolution"])


def shadows_section(now: dict[str, Any], before: dict[str, Any] | None) -> str:
    """The penumbra and leak tables, each row beside its before figure when there is one."""
    earlier = {key(row): row for row in (before or {}).get("rows", [])}
    penumbra, leak = [], []
    for row in now["rows"]:
        old = earlier.get(key(row))
        if row["kind"] == "penumbra":
            penumbra.append([
                row["mesh"], row["world"], str(row["light"]), str(row["shadow_resolution"]),
                str(row["pixels"]),
                percent(old["relative_rms"]) if old else "—", percent(row["relative_rms"]),
                percent(row["reference_noise"]),
                smoothness(old) if old else "—", smoothness(row)])
        else:
            leak.append([
                row["mesh"], row["world"], str(row["light"]), str(row["shadow_resolution"]),
                str(row["pixels"]), f"{row['reference_visibility']:.3f}",
                f"{old['visibility']:.3f}" if old else "—", f"{row['visibility']:.3f}"])
    sample = now["rows"][0] if now["rows"] else {"size": 0, "samples": 0}
    return "\n\n".join([
        "## Soft shadows",
        "One light's shadow (the rig's brightest; on the base every light), separated by "
        "linearity and compared as visibility with the reference's (`bench/shadow_sweep`, "
        f"{sample['size']}x{sample['size']}, the reference at {sample['samples']} samples of "
        "the light alone). Penumbra: ground pixels whose reference visibility (3x3 mean) is "
        "between 5 and 95 %. Error: relative RMS of visibility there. Smoothness: RMS of the "
        "high-pass visibility (less its Gaussian blur of 1 pixel), ours / the reference's less "
        "its Monte Carlo noise's expected share ('—' where that is below "
        f"{LEAST_REFERENCE_HIGH_PASS}). Before: the 16-point Poisson disc, unturned in the "
        "ground's bake, with its early exit; now: Vogel spirals, every tap. Only the floor drawn "
        "whole counts (within 5 scene radii; beyond, it fades into the background). 'studio' is "
        "Blender's, the same map before and now; 'default' is the built-in studio, whose "
        "before was measured under the previous one (the same three soft boxes over a "
        "near-black backdrop), so that its rows compare the filters under two lightings.",
        markdown_table(["mesh", "world", "light", "map", "pixels", "error before", "error now",
                        "reference noise", "high-pass before", "high-pass now"], penumbra),
        "The pole's shadow on the dress form's base (the base's top within half the pole's "
        "radius of the ray from the pole's axis to the light): mean visibility, the reference's, "
        "before and now; above the reference is light leaking through the pole.",
        markdown_table(["mesh", "world", "light", "map", "pixels", "reference", "before", "now"],
                       leak),
    ])
