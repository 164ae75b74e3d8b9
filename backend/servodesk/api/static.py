"""Serve the built frontend (one process, one port) with a fallback to index.html for the
browser's own routes."""

from __future__ import annotations

from pathlib import Path

from fastapi import FastAPI, HTTPException
from fastapi.responses import FileResponse, HTMLResponse
from fastapi.staticfiles import StaticFiles

NOT_BUILT = """<!doctype html><title>ServoDesk</title>
<p>The ServoDesk frontend is not built. Run <code>make run</code> (it builds it), or use the
API at <a href="/api/docs">/api/docs</a>.</p>"""


def mount_frontend(app: FastAPI, static_dir: Path) -> None:
    index = static_dir / "index.html"
    assets = static_dir / "assets"
    if assets.is_dir():
        app.mount("/assets", StaticFiles(directory=assets), name="assets")

    @app.get("/{path:path}", include_in_schema=False, response_model=None)
    async def frontend(path: str) -> FileResponse | HTMLResponse:
        if path.startswith("api/"):
            raise HTTPException(status_code=404, detail=f"no API route /{path}")
        candidate = (static_dir / path).resolve()
        if path and candidate.is_file() and static_dir.resolve() in candidate.parents:
            return FileResponse(candidate)
        if index.is_file():
            return FileResponse(index)
        return HTMLResponse(NOT_BUILT)
