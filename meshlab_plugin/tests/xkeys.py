#!/usr/bin/env python3
"""Types keys into the focused X window through the XTEST extension (libXtst, part of every
Xorg/Xvfb install) — a stand-in for xdotool, which the machine does not have.

  xkeys.py STEP...   STEP: "ctrl+f", "Return", "alt+Return", "text:some words", "sleep:1.5",
                     "move:X,Y" (pointer to screen pixel X,Y: without a window manager the
                     keyboard focus follows the pointer), "click:X,Y",
                     "wheel:N" (N notches at the pointer: > 0 away from the user, < 0 towards),
                     "waitlog:SECONDS:REGEX" (until a line of the file named by $XKEYS_LOG
                     matches REGEX, at most SECONDS: a filter's run time varies with the load)
Key names are X keysym names (Return, Escape, Tab, Down, F1, ...).
"""
import ctypes
import os
import re
import sys
import time

x11 = ctypes.cdll.LoadLibrary("libX11.so.6")
xtst = ctypes.cdll.LoadLibrary("libXtst.so.6")
x11.XOpenDisplay.restype = ctypes.c_void_p
x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
x11.XStringToKeysym.restype = ctypes.c_ulong
x11.XStringToKeysym.argtypes = [ctypes.c_char_p]
x11.XKeysymToKeycode.restype = ctypes.c_ubyte
x11.XKeysymToKeycode.argtypes = [ctypes.c_void_p, ctypes.c_ulong]
x11.XFlush.argtypes = [ctypes.c_void_p]
xtst.XTestFakeKeyEvent.argtypes = [ctypes.c_void_p, ctypes.c_uint, ctypes.c_int, ctypes.c_ulong]
xtst.XTestFakeMotionEvent.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_ulong]
xtst.XTestFakeButtonEvent.argtypes = [ctypes.c_void_p, ctypes.c_uint, ctypes.c_int, ctypes.c_ulong]

MODIFIERS = {"ctrl": "Control_L", "alt": "Alt_L", "shift": "Shift_L"}
SHIFTED = {"underscore", "colon", "plus", "question", "greater", "less", "parenleft", "parenright"}
CHARS = {" ": "space", "-": "minus", ".": "period", ":": "colon", "_": "underscore", "/": "slash"}


def keycode(display, name):
    sym = x11.XStringToKeysym(name.encode())
    if sym == 0:
        raise SystemExit(f"xkeys: unknown key {name!r}")
    return x11.XKeysymToKeycode(display, sym)


def press(display, combo):
    names = combo.split("+")
    keys = [MODIFIERS.get(n.lower(), n) for n in names]
    # Keysyms that share a key with another and need Shift on a US layout (underscore is on the
    # minus key: typed without Shift it comes out as "-").
    shift = len(keys) == 1 and ((len(keys[0]) == 1 and keys[0].isupper()) or keys[0] in SHIFTED)
    codes = ([keycode(display, "Shift_L")] if shift else []) + [keycode(display, k) for k in keys]
    for c in codes:
        xtst.XTestFakeKeyEvent(display, c, 1, 0)
        x11.XFlush(display)
        time.sleep(0.02)
    for c in reversed(codes):
        xtst.XTestFakeKeyEvent(display, c, 0, 0)
        x11.XFlush(display)
        time.sleep(0.02)


def wait_for_log(path, pattern, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            with open(path, errors="replace") as f:
                if any(pattern.search(line) for line in f):
                    return
        except OSError:
            pass
        time.sleep(0.5)
    print(f"xkeys: waitlog gave up after {seconds} s: no line of {path!r} matches {pattern.pattern!r}",
          file=sys.stderr)


def main():
    display = x11.XOpenDisplay(None)
    if not display:
        raise SystemExit("xkeys: cannot open the X display")
    for step in sys.argv[1:]:
        if step.startswith("sleep:"):
            time.sleep(float(step[6:]))
        elif step.startswith(("move:", "click:")):
            x, y = (int(v) for v in step.split(":", 1)[1].split(","))
            xtst.XTestFakeMotionEvent(display, -1, x, y, 0)
            x11.XFlush(display)
            if step.startswith("click:"):
                time.sleep(0.05)
                xtst.XTestFakeButtonEvent(display, 1, 1, 0)
                xtst.XTestFakeButtonEvent(display, 1, 0, 0)
                x11.XFlush(display)
        elif step.startswith("wheel:"):
            n = int(step[6:])
            for _ in range(abs(n)):
                button = 4 if n > 0 else 5
                xtst.XTestFakeButtonEvent(display, button, 1, 0)
                xtst.XTestFakeButtonEvent(display, button, 0, 0)
                x11.XFlush(display)
                time.sleep(0.1)
        elif step.startswith("waitlog:"):
            seconds, pattern = step[8:].split(":", 1)
            wait_for_log(os.environ.get("XKEYS_LOG", ""), re.compile(pattern), float(seconds))
        elif step.startswith("text:"):
            for ch in step[5:]:
                press(display, CHARS.get(ch, ch))
        else:
            press(display, step)
        time.sleep(0.1)


if __name__ == "__main__":
    main()
