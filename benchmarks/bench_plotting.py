"""Pictures of 3D pavings (issue 14 item 5): time to draw and save the boxes and three slices.

The pavings are the spherical shell 1/2 <= r <= 1 at three deltas (tens of thousands of boxes) and the SCARA's
certified workspace from ``reach``; each picture is drawn and saved as PNG (120 dpi), best of three.  The
reference in the same run is the previous drawing (every box as six translucent faces, two collections),
kept here only to compare.  Goal: a few seconds at most for 10^4 boxes.

    python benchmarks/bench_plotting.py
"""

import datetime
import tempfile
from pathlib import Path

import numpy as np

from _common import best_of, machine
from workspace_sym import StopAt, robots
from workspace_sym.interval import pave
from workspace_sym.plotting import plot_paving, plot_paving_slices, save_figure, slice_heights


def every_face(paving):
    """The previous 3D drawing: six faces per inner or boundary box, one translucent collection per kind."""
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig = plt.figure(figsize=(6, 5))
    ax = fig.add_subplot(projection="3d")
    for kind, colour, alpha in (("inner", "#4caf50", 0.5), ("boundary", "#ffd54f", 0.15)):
        faces = []
        for (x0, x1), (y0, y1), (z0, z1) in getattr(paving, kind):
            c = np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])
            for quad in ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)):
                faces.append(c[list(quad)])
        ax.add_collection3d(Poly3DCollection(faces, facecolors=colour, edgecolors="none", alpha=alpha))
    ax.set_xlim(paving.box.lower[0], paving.box.upper[0])
    ax.set_ylim(paving.box.lower[1], paving.box.upper[1])
    ax.set_zlim(paving.box.lower[2], paving.box.upper[2])
    return fig


def main():
    print(f"machine: {machine()}; {datetime.date.today()}")
    cases = [(f"shell, delta {d}", pave(["x**2 + y**2 + z**2 <= 1", "x**2 + y**2 + z**2 >= 0.25"],
                                        {"x": (-1.1, 1.1), "y": (-1.1, 1.1), "z": (-1.1, 1.1)}, delta=d,
                                        stop=StopAt(progress=False)))
             for d in (0.15, 0.1, 0.07)]
    cases.append(("SCARA reach, delta 0.04", robots.build("scara").reach(delta=0.04, stop=StopAt(progress=False))))
    print("| paving | inner + boundary boxes | 3D picture | previous 3D picture | three slices | PNG sizes |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        box3d, old3d, cut = Path(tmp) / "boxes.png", Path(tmp) / "old.png", Path(tmp) / "slices.png"
        for name, p in cases:
            drawn = len(p.inner) + len(p.boundary)
            t_new, _ = best_of(lambda p=p: save_figure(plot_paving(p, units="m"), box3d))
            t_old, _ = best_of(lambda p=p: save_figure(every_face(p), old3d))
            t_cut, _ = best_of(lambda p=p: save_figure(plot_paving_slices(p, values=slice_heights(p), units="m"), cut))
            sizes = f"{box3d.stat().st_size // 1024} KiB, {cut.stat().st_size // 1024} KiB"
            print(f"| {name} | {drawn} | {t_new:.2f} s | {t_old:.2f} s | {t_cut:.2f} s | {sizes} |")


if __name__ == "__main__":
    main()
