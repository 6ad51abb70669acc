"""``illuknit app``: start the local design app (a web page over the library)."""

from __future__ import annotations

import socket
import threading
import webbrowser

import click

from illuknit.core.errors import BackendUnavailableError


@click.command(name="app")
@click.option(
    "--port",
    type=click.IntRange(0, 65535),
    default=8765,
    show_default=True,
    help="Port to listen on (0 picks a free one).",
)
@click.option(
    "--host",
    default="127.0.0.1",
    show_default=True,
    help="Address to listen on. Keep the loopback default unless you mean to share the app.",
)
@click.option("--open", "open_browser", is_flag=True, help="Open the page in the default browser.")
def app(port: int, host: str, open_browser: bool) -> None:
    """Start the designer-in-the-loop app: load pictures, compare candidate tile mappings, edit
    tiles, watch the angled preview, and download pattern, chart, instructions and knitout.

    Needs the optional extra: pip install 'illuknit[app]'. Stop it with Ctrl-C.
    """
    try:
        import uvicorn
    except ImportError:
        raise BackendUnavailableError(
            "the app needs uvicorn and FastAPI: pip install 'illuknit[app]'"
        ) from None
    from illuknit.app import create_app

    asgi = create_app()
    # Bind first, so a busy port is one clear error line rather than a server log.
    try:
        sock = socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
    except OSError as e:
        raise click.UsageError(f"cannot listen on {host}:{port}: {e.strerror or e}") from None
    bound = sock.getsockname()[1]
    shown = "127.0.0.1" if host in ("0.0.0.0", "::") else host
    url = f"http://{shown}:{bound}/"
    click.echo(f"illuknit app: serving {url}  (API docs at {url}docs; Ctrl-C to stop)")
    if open_browser:
        threading.Timer(0.8, webbrowser.open, args=(url,)).start()
    config = uvicorn.Config(asgi, log_level="warning")
    server = uvicorn.Server(config)
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
