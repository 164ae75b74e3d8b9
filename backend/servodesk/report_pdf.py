"""The commissioning report's PDF, laid out in a process of its own.

WeasyPrint is mostly Python: in the server's process a report of a few pages would hold the
interpreter lock for a second or more in slices, and every stop the loop sends would wait for
its turn (DESIGN: bulk work goes to a process, as dictionary parses and log decodes do). This
module and WeasyPrint are all the worker imports (not the commissioning package: its services).
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from typing import Any

from servodesk.od.parser import lower_priority, worker_context


def render(html: str) -> bytes:
    """Called on a thread of the server (never the loop): one short-lived worker process."""
    context = worker_context(["servodesk.report_pdf"])
    with ProcessPoolExecutor(max_workers=1, mp_context=context, initializer=lower_priority) as pool:
        return pool.submit(_pdf, html).result()


def _refuse_fetch(url: str, *args: Any, **kwargs: Any) -> dict[str, Any]:
    # the page is self-contained: anything it would fetch is a mistake (or user text)
    raise ValueError(f"the report fetches nothing: {url}")


def _pdf(html: str) -> bytes:
    """In the worker process."""
    import weasyprint  # pango and its fonts load here, in the worker only

    document = weasyprint.HTML(string=html, url_fetcher=_refuse_fetch)
    pdf = document.write_pdf()
    if pdf is None:
        raise RuntimeError("WeasyPrint wrote no PDF")
    return bytes(pdf)
