#!/usr/bin/env python3
"""Screenshots of the filter in the real MeshLab 2020.09 GUI (issue 16), for docs/:
  screenshots.py PLUGIN OUTDIR      (e.g. build/libfilter_vn.so docs)
writes OUTDIR/meshlab-menu.png (Filters > Normals, Curvatures and Orientation,
the filter highlighted next to MeshLab's own) and OUTDIR/meshlab-dialog-help.png
(its dialog with Help pressed: every parameter's help must be readable there).

Stages MeshLab with every system plugin plus PLUGIN (as test_meshlab.py stages
meshlabserver), opens the Stanford bunny on an Xvfb of its own (1280x900) and
drives the menus with xdotool at the positions MeshLab 2020.09 puts them at
that size; ImageMagick's import takes the pictures. Installs xdotool and
imagemagick with apt-get when missing (as .ci/setup does). Exits 1 when the
filter's dialog does not open.
"""
import gzip
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import test_meshlab  # noqa: E402  (stage())

sys.path.insert(0, os.path.join(HERE, "..", "bench"))
from meshlab_speed import start_xvfb  # noqa: E402


def ensure_tools():
    missing = [p for p, tool in (("xdotool", "xdotool"), ("imagemagick", "import")) if not shutil.which(tool)]
    if missing:
        sudo = [] if os.geteuid() == 0 else ["sudo"]
        subprocess.run(sudo + ["apt-get", "install", "-y", "-qq", "--no-install-recommends"] + missing, check=True,
                       env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"), stdout=subprocess.DEVNULL)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    plugin, outdir = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    if not os.path.isfile(plugin):
        sys.exit("no plugin at %s (build it first: cmake --build build)" % plugin)
    os.makedirs(outdir, exist_ok=True)
    ensure_tools()
    tmp = tempfile.mkdtemp(prefix="vn-meshlab-shots-")
    xvfb = gui = None
    try:
        server = test_meshlab.stage(os.path.join(tmp, "ml"), plugin)
        meshlab = os.path.join(os.path.dirname(server), "meshlab")
        shutil.copy2(shutil.which("meshlab") or "/usr/bin/meshlab", meshlab)
        bunny = os.path.join(tmp, "bun_zipper.ply")
        with gzip.open(os.path.join(HERE, "data", "bun_zipper.ply.gz")) as g, open(bunny, "wb") as f:
            shutil.copyfileobj(g, f)

        xvfb, display = start_xvfb(size="1280x900x24")
        env = dict(os.environ, DISPLAY=display)
        gui = subprocess.Popen([meshlab, bunny], env=env, cwd=tmp, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)

        def xdo(*args):
            return subprocess.run(["xdotool"] + [str(a) for a in args], env=env, stdout=subprocess.PIPE,
                                  universal_newlines=True).stdout.split()

        def window(pattern, seconds=60):
            """The first visible window whose name matches the regular expression."""
            for _ in range(seconds * 10):
                ids = xdo("search", "--onlyvisible", "--name", pattern)
                if ids:
                    return ids[0]
                time.sleep(0.1)
            return None

        def shot(name, geometry):
            subprocess.run(["import", "-window", "root", "-crop", geometry, "+repage",
                            os.path.join(outdir, name)], env=env, check=True)
            print("wrote", os.path.join(outdir, name))

        main_window = window("MeshLab 2020.09")
        if not main_window:
            sys.exit("MeshLab's window did not appear")
        # The positions below are those of a 1280x900 main window; MeshLab may
        # still be laying itself out when it first maps the window.
        for _ in range(20):
            xdo("windowsize", main_window, 1280, 900)
            time.sleep(1)
            if "1280x900" in xdo("getwindowgeometry", main_window):
                break
        else:
            sys.exit("MeshLab's window did not take the size 1280x900")
        time.sleep(1)
        # Filters > Normals, Curvatures and Orientation > the filter, which
        # sorts right after MeshLab's own Re-Compute Vertex Normals.
        xdo("mousemove", 120, 10, "click", 1)
        time.sleep(1)
        # (the picture before the item's tooltip, the filter's description, covers the menu)
        for x, y, pause in ((245, 286, 0.5), (300, 286, 1.5), (600, 286, 0.5), (700, 662, 0.3)):
            xdo("mousemove", x, y)  # along the item's row into the submenu, then down in it
            time.sleep(pause)
        shot("meshlab-menu.png", "930x900+0+0")
        xdo("click", 1)
        dialog = window(re.escape(test_meshlab.FILTER), 20)
        if not dialog:
            sys.exit("the filter's dialog did not open")
        time.sleep(1.5)
        # Help: the right one of the two rows of buttons at the dialog's foot
        geometry = xdo("getwindowgeometry", dialog)
        x, y = (int(v) for v in geometry[geometry.index("Position:") + 1].split(","))
        w, h = (int(v) for v in geometry[geometry.index("Geometry:") + 1].split("x"))
        xdo("mousemove", x + 3 * w // 4, y + h - 54, "click", 1)
        time.sleep(1.5)
        geometry = xdo("getwindowgeometry", dialog)
        w, h = (int(v) for v in geometry[geometry.index("Geometry:") + 1].split("x"))
        shot("meshlab-dialog-help.png", "%dx%d+%d+%d" % (w + 2, h + 2, x, y))
    finally:
        if gui:
            gui.terminate()
            gui.wait()
        if xvfb:
            xvfb.terminate()
            xvfb.wait()
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
