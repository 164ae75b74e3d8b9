"""rerun's web viewer and its gRPC-web stream under ServoDesk's own origin, working offline.

- `GET /rerun/…`: the viewer's files from the app's RerunServer (scope/viewer_server.py),
  streamed. index.html is rewritten so the page reaches nothing beyond this origin (no Google
  Fonts, no analytics script, no update check, no welcome screen and its examples,
  cross-origin fetches refused) and served with a Content-Security-Policy that enforces it.
- `POST /rerun.sdk_comms.v1alpha1.MessageProxyService/{method}`: a viewer opened with
  `?url=rerun+http://{host}/proxy` reads the recordings with gRPC-web at the origin's root;
  forwarded to the RerunServer's gRPC port and streamed back as it arrives (a live stream never
  ends). Same origin, so no CORS: the security middlewares stay in front, unchanged.
- `GET /api/scope/viewer`: where the viewer is (starts it).
"""

from __future__ import annotations

import logging
import re
from collections.abc import AsyncIterator
from urllib.parse import quote

import anyio
import httpx
from fastapi import APIRouter, HTTPException, Request
from fastapi.responses import HTMLResponse, JSONResponse, RedirectResponse, Response
from starlette.responses import StreamingResponse

from servodesk.api.deps import ServicesDep
from servodesk.api.errors import body_response
from servodesk.errors import ScopeViewerError
from servodesk.models.common import ErrorBody
from servodesk.models.scope import ScopeViewer
from servodesk.scope.viewer_server import RerunServer

log = logging.getLogger(__name__)

VIEWER_PATH = "/rerun/"
GRPC_SERVICE = "rerun.sdk_comms.v1alpha1.MessageProxyService"
MAX_GRPC_REQUEST = 1 << 20  # the viewer's requests are a few bytes
_FILE = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")
_METHOD = re.compile(r"[A-Za-z][A-Za-z0-9]{0,63}")
_ASSET_HEADERS = ("content-type", "content-length", "content-encoding", "rerun-final-length")
_GRPC_REQUEST_HEADERS = (
    "content-type",
    "accept",
    "x-grpc-web",
    "x-user-agent",
    "grpc-timeout",
    "grpc-encoding",
    "grpc-accept-encoding",
)
_GRPC_RESPONSE_HEADERS = (
    "content-type",
    "grpc-status",
    "grpc-message",
    "grpc-status-details-bin",
    "grpc-encoding",
    "grpc-accept-encoding",
)
# What the page may load: this origin only (wasm needs wasm-unsafe-eval, the inline scripts
# and styles of rerun's index.html need unsafe-inline). The app may embed it (frame-ancestors).
CSP = "; ".join(
    (
        "default-src 'self'",
        "script-src 'self' 'unsafe-inline' 'wasm-unsafe-eval'",
        "style-src 'self' 'unsafe-inline'",
        "img-src 'self' data: blob:",
        "font-src 'self' data:",
        "media-src 'self' data: blob:",
        "worker-src 'self' blob:",
        "connect-src 'self'",
        "object-src 'none'",
        "base-uri 'self'",
        "form-action 'self'",
        "frame-ancestors 'self'",
    )
)
# First in <head>: fetch and sendBeacon to another origin fail at once, as offline (rerun's
# wasm posts analytics to tel.rerun.io and has no switch for it on the web).
_OFFLINE_GUARD = """<script>
(function () {
  function address(target) {
    return String(typeof target === "object" && target && "url" in target ? target.url : target);
  }
  function own(target) {
    try {
      return new URL(address(target), location.href).origin === location.origin;
    } catch (error) {
      return false;
    }
  }
  var fetch = window.fetch.bind(window);
  window.fetch = function (target, init) {
    if (!own(target)) {
      console.info("ServoDesk: the viewer works offline; not fetching " + address(target));
      return Promise.reject(new TypeError("offline viewer: no requests to other origins"));
    }
    return fetch(target, init);
  };
  if (navigator.sendBeacon) {
    var beacon = navigator.sendBeacon.bind(navigator);
    navigator.sendBeacon = function (target, data) {
      return own(target) ? beacon(target, data) : false;
    };
  }
})();
</script>"""
# Viewer options no URL parameter reaches: no GitHub release check; no welcome screen, whose
# examples manifest comes from app.rerun.io (the guard refuses it if a user opens the examples).
_OPTIONS = (
    "Object.assign(options, {hide_welcome_screen: true, check_for_updates_on_startup: false})"
)
_HANDLE = "new wasm_bindgen.WebHandle(options)"
_REMOTE_LINK = re.compile(r"<link\b[^>]*\bhref=\"(?:https?:)?//[^\"]*\"[^>]*>\s*", re.S)
_HOSTED_ANALYTICS = re.compile(
    r"if\s*\(\s*window\.location\.hostname\s*==+\s*\"app\.rerun\.io\"\s*\)\s*\{[^{}]*\}\s*"
)
_index_cache: dict[str, str] = {}  # build id → rewritten index.html (the binary's, immutable)

root_router = APIRouter(include_in_schema=False)
router = APIRouter(tags=["scope"])


def rewrite_index(html: str) -> str:
    """rerun's index.html made offline; a part that is not found is logged (the CSP still holds)."""
    rewritten = _REMOTE_LINK.sub("", html)
    rewritten = _HOSTED_ANALYTICS.sub("", rewritten)
    if "<head>" in rewritten:
        rewritten = rewritten.replace("<head>", "<head>\n" + _OFFLINE_GUARD, 1)
    else:
        log.warning("rerun's index.html has no <head>: the offline guard is not installed")
    if _HANDLE in rewritten:
        rewritten = rewritten.replace(_HANDLE, f"new wasm_bindgen.WebHandle({_OPTIONS})", 1)
    else:
        log.warning("rerun's index.html has no %s: viewer options not set", _HANDLE)
    return rewritten


def viewer_url(request: Request) -> tuple[str, str]:
    """(viewer page, gRPC URL the viewer connects to), both through the host the browser used."""
    host = request.headers.get("host") or request.url.netloc
    scheme = "rerun+https" if request.url.scheme == "https" else "rerun+http"
    grpc_url = f"{scheme}://{host}/proxy"
    return f"{VIEWER_PATH}?url={quote(grpc_url, safe='')}", grpc_url


@router.get(
    "/scope/viewer",
    response_model=ScopeViewer,
    responses={503: {"model": ErrorBody, "description": "The rerun viewer could not start"}},
)
async def scope_viewer(request: Request, services: ServicesDep) -> ScopeViewer | JSONResponse:
    """The embedded rerun viewer: its page under this origin and what it connects to."""
    viewer = services.viewer
    try:
        await viewer.ensure_started()
    except ScopeViewerError as error:
        return unavailable(error)
    url, grpc_url = viewer_url(request)
    return ScopeViewer(url=url, grpc_url=grpc_url, version=viewer.version, running=viewer.running)


@root_router.get("/rerun", response_model=None)
async def viewer_root(request: Request) -> RedirectResponse:
    query = request.url.query
    return RedirectResponse(VIEWER_PATH + (f"?{query}" if query else ""), status_code=307)


@root_router.get("/rerun/{path:path}", response_model=None)
async def viewer_file(path: str, request: Request, services: ServicesDep) -> Response:
    viewer = services.viewer
    if path not in ("", "index.html") and not _FILE.fullmatch(path):
        raise HTTPException(status_code=404, detail=f"the rerun viewer has no file {path!r}")
    if path in ("", "index.html"):
        try:
            html = await _index(viewer)
        except ScopeViewerError as error:
            return unavailable(error)
        headers = {"Cache-Control": "no-store", "Content-Security-Policy": CSP}
        return HTMLResponse(html, headers=headers)
    etag = f'"{viewer.build_id}-{path}"'
    if request.headers.get("if-none-match") == etag:
        return Response(status_code=304, headers={"ETag": etag})
    try:
        await viewer.ensure_started()
        upstream = await _send(viewer, "GET", f"{viewer.web_base}/{path}")
    except ScopeViewerError as error:
        return unavailable(error)
    if upstream.status_code == 404:
        await upstream.aclose()
        raise HTTPException(status_code=404, detail=f"the rerun viewer has no file {path!r}")
    headers = {name: upstream.headers[name] for name in _ASSET_HEADERS if name in upstream.headers}
    if headers.get("content-type", "").startswith("text/html"):
        headers["Content-Security-Policy"] = CSP
    if upstream.status_code == 200:  # revalidated each time: 304 until the rerun binary changes
        headers.update({"ETag": etag, "Cache-Control": "no-cache"})
    return StreamingResponse(_relay(upstream), status_code=upstream.status_code, headers=headers)


@root_router.post(f"/{GRPC_SERVICE}/{{method}}", response_model=None)
async def grpc_web(method: str, request: Request, services: ServicesDep) -> Response:
    """gRPC-web from the viewer (ReadMessages: the live recordings) to rerun's gRPC port."""
    if not _METHOD.fullmatch(method):
        raise HTTPException(status_code=404, detail=f"no gRPC method {method!r}")
    if not request.headers.get("content-type", "").startswith("application/grpc-web"):
        raise HTTPException(status_code=415, detail="send gRPC-web (application/grpc-web+proto)")
    body = await _grpc_body(request)
    headers = {k: request.headers[k] for k in _GRPC_REQUEST_HEADERS if k in request.headers}
    viewer = services.viewer
    try:
        await viewer.ensure_started()
        upstream = await _send(
            viewer,
            "POST",
            f"{viewer.grpc_base}/{GRPC_SERVICE}/{method}",
            content=body,
            headers=headers,
            timeout=httpx.Timeout(10.0, read=None),  # a live stream may idle for long
        )
    except ScopeViewerError as error:
        return unavailable(error)
    kept = {k: upstream.headers[k] for k in _GRPC_RESPONSE_HEADERS if k in upstream.headers}
    return StreamingResponse(_relay(upstream), status_code=upstream.status_code, headers=kept)


def unavailable(error: ScopeViewerError) -> JSONResponse:
    return body_response(503, ErrorBody(error="scope_viewer_unavailable", message=str(error)))


async def _index(viewer: RerunServer) -> str:
    await viewer.ensure_started()
    build = viewer.build_id
    if build not in _index_cache:
        response = await _send(viewer, "GET", f"{viewer.web_base}/index.html", stream=False)
        if response.status_code != 200:
            raise ScopeViewerError(
                f"the rerun viewer answered {response.status_code} for its page; see "
                f"{viewer.log_path}"
            )
        _index_cache[build] = rewrite_index(response.text)
    return _index_cache[build]


async def _send(
    viewer: RerunServer,
    method: str,
    url: str,
    *,
    content: bytes | None = None,
    headers: dict[str, str] | None = None,
    timeout: httpx.Timeout | None = None,
    stream: bool = True,
) -> httpx.Response:
    client = viewer.client
    request = client.build_request(
        method, url, content=content, headers=headers, timeout=timeout or client.timeout
    )
    try:
        response = await client.send(request, stream=stream)
    except httpx.HTTPError as error:
        raise ScopeViewerError(
            f"the scope viewer (rerun) does not answer: {error}; reload the page to restart it"
        ) from error
    return response


async def _grpc_body(request: Request) -> bytes:
    body = bytearray()
    async for chunk in request.stream():
        body += chunk
        if len(body) > MAX_GRPC_REQUEST:
            raise HTTPException(status_code=413, detail="gRPC-web request larger than 1 MiB")
    return bytes(body)


async def _relay(upstream: httpx.Response) -> AsyncIterator[bytes]:
    """The upstream body as it arrives; closed when the browser goes (Starlette cancels us)."""
    try:
        async for chunk in upstream.aiter_raw():
            yield chunk
    except httpx.HTTPError as error:
        # rerun stopped (app shutdown, crash): the stream ends, the viewer shows it disconnected
        log.info("rerun stream to the viewer ended: %s", error)
    finally:
        with anyio.CancelScope(shield=True):
            await upstream.aclose()
