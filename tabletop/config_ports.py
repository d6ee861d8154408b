"""UDP port checks of a config: ``osc`` sources, ``tuio`` sinks and the kiosk heartbeat on this
machine's ports. Each refusal is one line naming the key, raised through the config's
:class:`~tabletop.schema.Context`."""

from __future__ import annotations

import ipaddress
from pathlib import Path

from tabletop.schema import Context


def _loopback(host: str) -> bool:
    try:
        return host == "localhost" or ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _reaches(sender: str, listener: str) -> bool:
    """Whether datagrams sent to host ``sender`` arrive at a socket bound to ``listener`` on
    this machine (the same address, or loopback to a loopback or any-interface socket)."""
    return sender == listener or (_loopback(sender) and (_loopback(listener)
                                                         or listener in ("0.0.0.0", "::")))


def osc_listeners(cfg: dict) -> list[tuple[str, str, int]]:
    """(key path, host, port) of every ``osc`` source of ``cfg``."""
    return [(f"sources[{i}]", s["host"], s["port"]) for i, s in enumerate(cfg["sources"])
            if s["kind"] == "osc"]


def own_osc(cfg: dict, host: str, port: int) -> str | None:
    """The key path of this installation's own ``osc`` source that datagrams sent to
    ``host``:``port`` arrive at, else None."""
    for key, o_host, o_port in osc_listeners(cfg):
        if port == o_port and _reaches(host, o_host):
            return key
    return None


def check_udp_ports(cfg: dict, ctx: Context) -> None:
    """Two ``osc`` sources listening on one port (the second could never bind: it would retry
    for ever), and a ``tuio`` sink sending to this installation's own ``osc`` source (every
    puck would come back as a second sighting, and every character as a puck: a feedback
    loop); in a kiosk config, :func:`check_heartbeat` too."""
    listening = osc_listeners(cfg)
    for n, (key, host, port) in enumerate(listening):
        for other, o_host, o_port in listening[:n]:
            if port == o_port and (_reaches(host, o_host) or _reaches(o_host, host)):
                raise ctx.error(f"{key}.port", f"port {port} is also {other}'s; only one "
                                               "socket can listen on it: give another")
    for i, k in enumerate(cfg["sinks"]):
        key = own_osc(cfg, k["host"], k["port"]) if k["kind"] == "tuio" else None
        if key is not None:
            raise ctx.error(f"sinks[{i}].port", f"{k['host']}:{k['port']} is this "
                            f"installation's own {key} (osc): its pucks and characters would "
                            "come back as pucks; send to another port or machine")
    if cfg["kiosk"]["enabled"]:
        check_heartbeat(cfg, ctx)


def check_heartbeat(cfg: dict, ctx: Context | None = None) -> None:
    """Refuse a kiosk heartbeat sent to this installation's own ``osc`` source: every second
    it would arrive there as an unknown message, logged and shown in that source's health
    ("ignored: N unknown address"), while no monitor hears the table. Checked when a kiosk
    config is validated, by ``run --kiosk`` for a config whose kiosk is off, and before a
    kiosk applies an edited config (``cfg`` then a :class:`~tabletop.config.Config`, naming
    its file)."""
    if ctx is None:
        ctx = Context(file=str(cfg.file), base=Path(cfg.base))
    hb = cfg["kiosk"]["heartbeat"]
    key = own_osc(cfg, hb["host"], hb["port"]) if hb["enabled"] else None
    if key is not None:
        raise ctx.error("kiosk.heartbeat.port", f"{hb['host']}:{hb['port']} is this "
                        f"installation's own {key} (osc): the heartbeats would arrive "
                        "there as unknown messages; send them to another port or machine")
