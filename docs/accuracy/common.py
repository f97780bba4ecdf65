"""What every part of the report shares: number formats, markdown tables, the Pareto front."""

from collections.abc import Iterable, Sequence
from typing import Callable, TypeVar

Point = TypeVar("Point")

# model-viewer's render-fidelity test fails a renderer whose difference is above this (dB).
FIDELITY_BOUND_DB = -22.0
# The noise requirement: the reference's noise below a fifth of the error it measures.
NOISE_RATIO_LIMIT = 0.2
MISSING = "—"


def minus(text: str) -> str:
    """A number's text with a true minus sign, as the report's prose and tables print it."""
    return text.replace("-", "−")


def percent(fraction: float, digits: int = 1) -> str:
    """A fraction as a percentage, "13.1 %"."""
    return minus(f"{100.0 * fraction:.{digits}f} %")


def signed_percent(fraction: float, digits: int = 1) -> str:
    """A signed error as a percentage, "+1.1 %" or "−3.4 %"."""
    return minus(f"{100.0 * fraction:+.{digits}f} %")


def decibels(value: float) -> str:
    """A fidelity figure in dB with a true minus sign, "−24.3"."""
    return minus(f"{value:.1f}")


def milliseconds(value: float) -> str:
    """A time in ms, one decimal above 1 ms and three below (projections take microseconds)."""
    return f"{value:.1f}" if value >= 1.0 else f"{value:.3f}"


def value_range(values: Iterable[float], format_value: Callable[[float], str]) -> str:
    """"a–b" over the values, or the one value when they agree to the format."""
    ordered = sorted(values)
    low, high = format_value(ordered[0]), format_value(ordered[-1])
    return low if low == high else f"{low.removesuffix(' %')}–{high}"


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A GitHub markdown table; an empty table is a bug upstream, so it raises."""
    if not rows:
        raise ValueError(f"empty table under header {list(header)}")
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def dominator(point: Point, points: Iterable[Point], time: Callable[[Point], float],
              error: Callable[[Point], float]) -> Point | None:
    """The fastest point both faster and more accurate than `point`, or None when it is on the
    front (lower-left Pareto front of time against error)."""
    better = [other for other in points
              if time(other) < time(point) and error(other) < error(point)]
    return min(better, key=time) if better else None


def pareto_front(points: Iterable[Point], time: Callable[[Point], float],
                 error: Callable[[Point], float]) -> list[Point]:
    """The points no other point dominates, fastest first."""
    candidates = list(points)
    front = [point for point in candidates if dominator(point, candidates, time, error) is None]
    return sorted(front, key=time)
