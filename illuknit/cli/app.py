"""``illuknit app``: start the local design app (a web page over the library)."""

from __future__ import annotations

import ipaddress
import socket
import threading
import webbrowser
from pathlib import Path

import click

from illuknit.cli.options import DAYS, FiniteFloat
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
    help="Address to listen on. Keep the loopback default unless you mean to share the app: "
    "any other address is warned about; an empty one is the loopback address.",
)
@click.option("--open", "open_browser", is_flag=True, help="Open the page in the default browser.")
@click.option(
    "--data-dir",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Folder the sessions are saved in  [default: the per-user data folder, "
    "e.g. ~/.local/share/illuknit/app]",
)
@click.option(
    "--keep-days",
    type=DAYS,
    default=30.0,
    show_default=True,
    help="Delete a saved session unused for this many days.",
)
@click.option(
    "--keep-mb",
    type=FiniteFloat(min=1, max=1024 * 1024),
    default=2048.0,
    show_default=True,
    help="Saved sessions together take at most this much disk; the least recently used go first.",
)
@click.option(
    "--memory-mb",
    type=FiniteFloat(min=0, max=1024 * 1024),
    default=512.0,
    show_default=True,
    help="Sessions together hold at most this much memory; the least recently used leave memory "
    "(they stay saved, and come back when their page asks).",
)
def app(
    port: int,
    host: str,
    open_browser: bool,
    data_dir: Path | None,
    keep_days: float,
    keep_mb: float,
    memory_mb: float,
) -> None:
    """Start the designer-in-the-loop app: load pictures, compare candidate tile mappings, edit
    tiles, watch the angled preview, and download pattern, chart, instructions and knitout.

    Work is saved as it is made (in --data-dir), so stopping the app, a crash or a reboot loses
    nothing: reload the page to carry on.

    Needs the optional extra: pip install 'illuknit[app]'. Stop it with Ctrl-C.
    """
    try:
        import uvicorn
    except ImportError:
        raise BackendUnavailableError(
            "the app needs uvicorn and FastAPI: pip install 'illuknit[app]'"
        ) from None
    from illuknit.app import create_app
    from illuknit.app.server import AppConfig
    from illuknit.app.store import default_data_dir

    # Bind first, before the data folder and its database are made: a bad address or a busy
    # port is one clear error line, and leaves nothing behind.
    sock, shown, loopback = listen(host, port)
    folder = data_dir if data_dir is not None else default_data_dir()
    try:
        asgi = create_app(
            AppConfig(
                data_dir=folder,
                keep_days=keep_days,
                keep_bytes=int(keep_mb * 2**20),
                max_session_bytes=int(memory_mb * 2**20),
            )
        )
    except BaseException:
        sock.close()
        raise
    url = f"http://{shown}:{sock.getsockname()[1]}/"
    if not loopback:
        click.echo(
            f"illuknit app: WARNING: listening on {sock.getsockname()[0]}, not on this machine "
            "alone: anyone who can reach it over the network can open the app, see every "
            "saved design and change it. Stop it (Ctrl-C) unless you mean to share it; "
            "--host 127.0.0.1 keeps it to this machine.",
            err=True,
        )
    click.echo(f"illuknit app: serving {url}  (API docs at {url}docs; Ctrl-C to stop)")
    click.echo(f"illuknit app: sessions are saved in {folder}")
    if open_browser:
        threading.Timer(0.8, webbrowser.open, args=(url,)).start()
    config = uvicorn.Config(asgi, log_level="warning")
    server = uvicorn.Server(config)
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()


#: Every interface: a listening address that is no single interface (a browser cannot open it).
_ANY = ("0.0.0.0", "::")


def listen(host: str, port: int) -> tuple[socket.socket, str, bool]:
    """A socket bound to ``host``:``port``, the host as a browser's address names it, and
    whether only this machine can reach it (loopback).

    An empty ``host`` is the loopback address (never every interface, as ``bind`` would take
    it); a name is resolved; an address that is not one, or a port in use, is a
    :class:`click.UsageError` naming it.
    """
    host = host.strip() or "127.0.0.1"
    try:
        family, _, _, _, address = socket.getaddrinfo(
            host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE
        )[0]
    except (socket.gaierror, UnicodeError, ValueError) as e:
        raise click.UsageError(
            f"--host {host!r} is not an address this machine can listen on ({getattr(e, 'strerror', e) or e}); "
            "use 127.0.0.1 (this machine only) or one of its network addresses"
        ) from None
    ip = ipaddress.ip_address(str(address[0]).split("%")[0])
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(address)
    except OSError as e:
        sock.close()
        raise click.UsageError(f"cannot listen on {host}:{port}: {e.strerror or e}") from None
    shown = "127.0.0.1" if str(ip) in _ANY else str(ip)
    if ip.version == 6 and str(ip) not in _ANY:
        shown = f"[{shown}]"
    return sock, shown, ip.is_loopback
