"""The unattended gallery table: supervision, health, attract mode and live configuration.

- :mod:`~tabletop.kiosk.supervisor` runs the installation in a child process and restarts it
  after a crash (with back-off and a crash log) or a stall (no frame for ``stall_s``),
  each run a :mod:`~tabletop.kiosk.child` (its process, warm spare, stderr tail);
  :mod:`~tabletop.kiosk.supervised` is that child's side (it ends when the supervisor is gone);
  :mod:`~tabletop.kiosk.paths` names the kiosk's own files (status, logs, last good config);
- :mod:`~tabletop.kiosk.notify` speaks systemd's notify protocol (READY, WATCHDOG) from the
  frame loop;
- :mod:`~tabletop.kiosk.health` writes the status JSON file, sends the OSC heartbeat and keeps
  a rotating log;
- :mod:`~tabletop.kiosk.attract` plays scripted pucks when nobody is at the table and shows the
  calm "one moment" screen while a vanished input reconnects;
- :mod:`~tabletop.kiosk.watch` applies ``config.yaml`` edits made on disk (or refuses them).

The ``kiosk:`` section of config.yaml is :data:`tabletop.kiosk.settings.SCHEMA`, in a module
of its own: a part of the kiosk (its lock, its supervisor) imported alone loads none of the
plugins the section is checked with, nor numpy (a process taking the lock: 0.42 -> 0.1 CPU s).
"""
