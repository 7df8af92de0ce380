"""The paper's Fig. 5 from Python alone: normalized contrast against
accommodation for gratings at the scene's target depths (paper: 0.7, 1.3 and
1.9 D) and frequencies (2 and 4 cpd), the display beside natural viewing.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/fig5.py [SCENE.json] [OUT.png]

SCENE defaults to examples/paper_prototype.json (its "run" section's
"contrast" object gives the depths and frequencies), OUT to fig5.png.
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402

import layerlab  # noqa: E402

root = pathlib.Path(__file__).resolve().parents[2]
scene = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else root / "examples" / "paper_prototype.json"
out = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else pathlib.Path("fig5.png")

curves = layerlab.contrast(scene)
frequencies = sorted({c["frequency"] for c in curves})
depths = sorted({c["target_diopters"] for c in curves})
colors = dict(zip(depths, plt.rcParams["axes.prop_cycle"].by_key()["color"]))

fig, axes = plt.subplots(1, len(frequencies), figsize=(5 * len(frequencies), 3.8), sharey=True, squeeze=False)
for ax, f in zip(axes[0], frequencies):
    for c in (c for c in curves if c["frequency"] == f):
        natural = c["display"] == "natural"
        ax.plot(c["accommodation"], c["contrast"], color=colors[c["target_diopters"]], linestyle="--" if natural else "-",
                label=f"{c['display']}, {c['target_diopters']:g} D")
    for d in depths:
        ax.axvline(d, color=colors[d], linewidth=0.6, alpha=0.5)
    ax.set_title(f"{f:g} cpd")
    ax.set_xlabel("accommodation (D)")
    ax.grid(alpha=0.3)
axes[0][0].set_ylabel("normalized contrast")
axes[0][-1].legend(fontsize=7)
fig.suptitle(curves[-1]["convention"], fontsize=8)
fig.tight_layout()
fig.savefig(out, dpi=120)
for c in curves:
    print(f"{c['display']:>24} {c['target_diopters']:.1f} D {c['frequency']:g} cpd: peak {c['peak']:.2f} D"
          f" +- {c['peak_uncertainty']:.2f}{' (flat)' if c['flat'] else ''}")
print(f"wrote {out}")
