"""Figures of layerlab's results with matplotlib (Debian's python3-matplotlib), as the run report draws them.

    import layerlab, layerlab.plot
    solution = layerlab.solve(scene, iterations=30)
    layerlab.plot.patterns(solution).savefig("patterns.png")
    layerlab.plot.psnr_against_time(solution.report).savefig("psnr.png")
    diopters, images = layerlab.focal_stack(solution, 0.4, 2.2, 0.6)
    layerlab.plot.retina(images, diopters).savefig("retina.png")
    layerlab.plot.contrast(layerlab.contrast(scene.file)).savefig("contrast.png")

Each function returns a matplotlib Figure (nothing is shown); pictures are sRGB-encoded with layerlab.srgb
and drawn one image pixel to one data unit, without smoothing.
"""

from . import _layerlab


def _pyplot():
    import matplotlib.pyplot as plt  # without a display matplotlib falls back to Agg by itself

    return plt


def _images(pictures, titles, columns, white=1.0):
    plt = _pyplot()
    rows = (len(pictures) + columns - 1) // columns
    figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 2.6 * rows), squeeze=False)
    for k, ax in enumerate(axes.flat):
        if k < len(pictures):
            ax.imshow(_layerlab.srgb(pictures[k], white=white), interpolation="nearest")
            ax.set_title(titles[k], fontsize=10)
        ax.axis("off")
    figure.tight_layout()
    return figure


def patterns(solution, columns=2, *, system=None):
    """Each layer's pattern in the eye's orientation (Solution.patterns_as_seen), titled with its layer and
    depth: transmittance, sRGB-encoded (1 = white). `solution`: a layerlab.Solution, or, with `system` (a
    layerlab.System), a list of one (rows, cols, 3) array per layer (patterns of your own)."""
    if system is None:
        system, seen = solution.system, solution.patterns_as_seen
    else:
        seen = _layerlab.patterns_as_seen(system, list(solution))
    titles = [f"{layer.name} ({layer.diopters:.2f} D)" for layer in system.layers]
    return _images(seen, titles, columns)


def retina(images, diopters, columns=3, white=1.0):
    """Retinal images (states, rows, cols, 3), display-relative linear light as Solution.retina and
    focal_stack give them, one panel per accommodation state (`diopters`, D)."""
    if len(images) != len(diopters):
        raise ValueError(f"retina: {len(images)} images but {len(diopters)} accommodation states")
    return _images(list(images), [f"focused at {d:.2f} D" for d in diopters], columns, white)


def psnr_against_time(*reports, labels=None):
    """Light-field PSNR (dB) against wall time (s), from iteration 0, one line per report (a solve's
    Solution.report), each point marked."""
    plt = _pyplot()
    figure, ax = plt.subplots(figsize=(6.4, 3.8))
    markers = "osD^v<>"
    for k, report in enumerate(reports):
        trace = report["trace"]
        label = labels[k] if labels else report["solver"]
        ax.plot(trace["seconds"], trace["psnr_db"], marker=markers[k % len(markers)], markerfacecolor="none",
                label=label)
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("PSNR (dB)")
    ax.set_title("light-field PSNR against wall time")
    ax.grid(alpha=0.3)
    ax.legend()
    figure.tight_layout()
    return figure


def contrast(curves, frequency=None):
    """Normalized contrast against accommodation (the paper's Fig. 5) from contrast()'s dicts: one panel
    per target depth, one line per display (natural viewing dashed), the target depth a grey band; only
    `frequency` (cpd) when given."""
    plt = _pyplot()
    chosen = [c for c in curves if frequency is None or c["frequency"] == frequency]
    if not chosen:
        raise ValueError(f"contrast: no curve at {frequency} cpd")
    depths = sorted({c["target_diopters"] for c in chosen})
    figure, axes = plt.subplots(1, len(depths), figsize=(4.6 * len(depths), 3.6), squeeze=False)
    for ax, depth in zip(axes.flat, depths):
        ax.axvspan(depth - 0.02, depth + 0.02, color="0.6", alpha=0.35, label="target depth")
        for c in chosen:
            if c["target_diopters"] != depth:
                continue
            natural = c["display"] == "natural"
            ax.plot(c["accommodation"], c["contrast"], linestyle="--" if natural else "-",
                    label=f"{c['display']}, {c['frequency']:g} cpd")
        ax.set_title(f"target at {depth:.2f} D")
        ax.set_xlabel("accommodation (D)")
        ax.set_ylabel("normalized contrast")
        ax.grid(alpha=0.3)
    axes.flat[0].legend(fontsize=8)
    figure.tight_layout()
    return figure
