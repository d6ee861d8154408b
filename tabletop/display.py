"""The display every window of the program opens on (the projector view, the live calibration
windows): SDL's display started, a display named but not there refused, the window's size.

Apart from :mod:`tabletop.view` (whose drawing modules load the compiled kernels, numba
among them: 0.45-0.55 of the ~0.9-1.1 CPU s of a run or a live calibration refused for want
of its display), so that a start the display refuses is told before those load.
"""

from __future__ import annotations

import os

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import pygame  # noqa: E402

from tabletop.errors import InputError  # noqa: E402

# what to do when the display cannot be opened (check_driver), said for the projector view
WITHOUT_WINDOW = "run without a window (--headless or view.headless)"


def headless_needed(force: bool) -> bool:
    """True when the view must use SDL's dummy driver: forced, or no display to open."""
    if force:
        return True
    if os.environ.get("SDL_VIDEODRIVER"):
        return os.environ["SDL_VIDEODRIVER"] in ("dummy", "offscreen")
    return not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
                or os.name == "nt" or os.uname().sysname == "Darwin")


def init_display(headless: bool) -> None:
    """``pygame.display.init``; where only an X display is named, SDL tries X11 and then its
    offscreen driver (which :func:`check_driver` refuses) and no Wayland: probing Wayland when
    X cannot be opened, libwayland printed "error: XDG_RUNTIME_DIR is invalid or not set in
    the environment." above the refusal under a system service (which has no runtime folder).
    An SDL that takes no list of drivers keeps its own order."""
    env = os.environ
    if headless or env.get("SDL_VIDEODRIVER") or env.get("WAYLAND_DISPLAY") \
            or not env.get("DISPLAY"):
        pygame.display.init()
        return
    env["SDL_VIDEODRIVER"] = "x11,offscreen"
    try:
        pygame.display.init()
    except pygame.error:
        env.pop("SDL_VIDEODRIVER", None)
        pygame.display.init()
    finally:
        env.pop("SDL_VIDEODRIVER", None)


def start_display(headless: bool, instead: str = WITHOUT_WINDOW) -> None:
    """The display every window of the program opens on (the projector view, the live
    calibration windows): :func:`init_display`; with a window, a display named but not there
    refused in one line (:func:`check_driver`, ``instead`` saying what to do without one);
    then :func:`direct_framebuffer`."""
    init_display(headless)
    if not headless:
        check_driver(instead)
    direct_framebuffer()


def start_view_display(asked: bool) -> bool:
    """The projector view's display started (:func:`start_display`): SDL's dummy driver when
    the view runs headless, ``asked`` (``--headless`` or ``view.headless``) or with no display
    to open; returns whether it does. Called again by the view itself, it changes nothing."""
    headless = headless_needed(asked)
    if headless:
        os.environ["SDL_VIDEODRIVER"] = "dummy"
    start_display(headless)
    return headless


def check_driver(instead: str = WITHOUT_WINDOW) -> None:
    """Refuse (InputError) a display that is named (``DISPLAY``, ``WAYLAND_DISPLAY``) but
    cannot be opened, such as an X server that died or restarts: SDL then falls back to its
    offscreen driver, which would draw into no window while the status says "live" (Xvfb
    killed under a kiosk: the restarted installation ran offscreen at 29 fps and did not open
    the window when the server was back). Refused, a kiosk's supervisor restarts the
    installation until the display opens."""
    driver = pygame.display.get_driver()
    if driver not in ("offscreen", "dummy"):
        return
    named = ", ".join(f"{k}={os.environ[k]}" for k in ("DISPLAY", "WAYLAND_DISPLAY")
                      if os.environ.get(k))
    raise InputError(f"the display ({named}) cannot be opened: SDL found only its {driver} "
                     f"driver; start the display, or {instead}")


def check_display(index: int) -> int:
    """``view.display`` if this machine has that display, else a ConfigError naming the key."""
    n = pygame.display.get_num_displays()
    if not 0 <= index < n:
        from tabletop.schema import ConfigError
        raise ConfigError(f"view.display: display {index} does not exist; this machine has {n} "
                          f"display(s), 0 to {n - 1}")
    return index


def direct_framebuffer() -> None:
    """On X11, present the window's pixels straight to the X server (shared-memory images)
    rather than through SDL's default texture framebuffer, which uploads every frame into an
    OpenGL texture: without a GPU (Mesa's software OpenGL, Xvfb) that costs 15-30 ms per
    present, straight it costs under 1 ms (bench/view.py). Other video drivers keep SDL's
    choice (Wayland has no straight way); ``SDL_FRAMEBUFFER_ACCELERATION`` set by the operator
    wins. Call after ``pygame.display.init`` and before the window opens."""
    if pygame.display.get_driver() == "x11":
        os.environ.setdefault("SDL_FRAMEBUFFER_ACCELERATION", "0")


def window_size(size: tuple[int, int], desktop: tuple[int, int]) -> tuple[int, int]:
    """The window to open for ``view.size`` on a desktop of ``desktop`` pixels: ``size``, or,
    when it does not fit (a 1280x720 view on an 800x600 screen would show only its middle, the
    table's edges and pucks near them beyond the screen), the largest of its shape that does."""
    k = min(1.0, desktop[0] / size[0], desktop[1] / size[1])
    return size if k >= 1.0 else (max(1, int(size[0] * k)), max(1, int(size[1] * k)))
