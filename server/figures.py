"""PNG figures and CSV tables of stored results, made on request in the API's thread pool.

What a kind's figure shows is the kind's own (`Kind.draw` in `server/kinds/<name>.py`); this
module gives it a canvas. Figures use matplotlib's object API with the Agg canvas (no pyplot),
which keeps no global state and so is safe in several request threads at once.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from server.kinds import KINDS

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def records_csv(records: list[dict[str, Any]], columns: Sequence[str] = ()) -> str:
    """`columns` first (the header an empty table still has), then any others in first-seen
    order over all rows, so rows of different shapes still line up."""
    header = list(columns)
    for row in records:
        header.extend(k for k in row if k not in header)
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=header, lineterminator="\n")
    writer.writeheader()
    for row in records:
        writer.writerow({k: _cell(v) for k, v in row.items()})
    return buf.getvalue()


def _cell(v: Any) -> Any:
    if isinstance(v, list | dict):
        return repr(v)
    return "" if v is None else v


def figure(kind: str, spec: dict[str, Any], result: dict[str, Any]) -> Figure:
    """The figure of a done job of `kind` from its stored spec and result, drawn by the kind
    (`Kind.draw`) on a 6.4 x 4.8 in, 100 dpi canvas it may resize; apart from its PNG so that
    a test reads its titles and axis labels."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.8), dpi=100)
    FigureCanvasAgg(fig)
    KINDS[kind].draw(fig, spec, result)
    fig.tight_layout()
    return fig


def figure_png(kind: str, spec: dict[str, Any], result: dict[str, Any]) -> bytes:
    """`figure` as PNG bytes."""
    buf = io.BytesIO()
    figure(kind, spec, result).savefig(buf, format="png")
    return buf.getvalue()
