"""Make ``docs/figures/afm_walkthrough.png``, the figure of the README's CR-AFM walkthrough.

.venv/bin/python scripts/make_readme_figures.py [OUT.png]

(a) Contact resonances of modes 1-3 against κ = k*/k_c for the example lever (tip at r = 0.95;
Euler-Bernoulli beam, U. Rabe et al., Rev. Sci. Instrum. 67, 3281 (1996)), with the free
(κ = 0) and pinned (κ → ∞, evaluated at κ = 1e9) limits and the κ of the Cu grains.
(b) The M_sample map that ``contactres afm invert`` recovers from the README's example table
(:func:`contactres.example_afm_map` with the same arguments as the README), in GPa.

Deterministic: seeded data, the Agg backend and no time stamp in the PNG. Prints the recovered
M per named grain (the numbers quoted in the README).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # before pyplot: no display, the same pixels on every machine

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullFormatter

import contactres as cr
from contactres.measurements import NAMED_SURFACES, ExampleLever
from contactres.measurements.schema import AFM_TABLE

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "afm_walkthrough.png"
#: The README's call: cr.example_afm_map((64, 64), noise=50.0, seed=0).
MAP_ARGS = dict(shape=(64, 64), noise=50.0, seed=0)
KAPPA = np.logspace(-2, 4, 241)
PINNED_KAPPA = 1e9  # β is within ~1/κ of its κ → ∞ limit: indistinguishable on the plot


def inverted_map():
    """(table, truth, result) of the README's example, inverted as the CLI does."""
    table, truth = cr.example_afm_map(**MAP_ARGS, truth=True)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "resonances.csv"
        table.to_csv(path, index=False)
        result = cr.invert_afm_table(cr.read_resonance_table(path, AFM_TABLE), str(path))
    return table, truth, result


def frequency_panel(ax, kappa_grains) -> None:
    lever = ExampleLever()
    cant, r = lever.cantilever(), lever.tip_position
    f = cr.contact_frequencies(cant, KAPPA, r, modes=(1, 2, 3)) / 1e6
    free = cr.contact_frequencies(cant, 0.0, r, modes=(1, 2, 3)) / 1e6
    pinned = cr.contact_frequencies(cant, PINNED_KAPPA, r, modes=(1, 2, 3)) / 1e6
    colors = ("C0", "C1", "C2")
    for n in range(3):
        ax.plot(KAPPA, f[:, n], color=colors[n], lw=1.8)
        ax.axhline(free[n], color=colors[n], ls="--", lw=0.9)
        ax.axhline(pinned[n], color=colors[n], ls="-.", lw=0.9)
        # Mode labels at the left end, just above the flat start of each curve (the free line):
        # every other line is at least 20 % away there, so no label or legend box covers a curve.
        ax.text(0.012, free[n] * 1.04, f"mode {n + 1}", color=colors[n], va="bottom")
    ax.axvspan(kappa_grains.min(), kappa_grains.max(), color="0.6", alpha=0.35, lw=0)
    # Beside the band, below mode 1's saturated branch: the empty lower right of the panel.
    ax.text(kappa_grains.max() * 1.3, 0.3, "← the Cu grains of (b), κ ≈ 30", fontsize=8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(KAPPA[0], KAPPA[-1])
    ax.set_ylim(0.12, 9.0)
    # Plain numbers on the log axis (the default 2 × 10⁰ labels are hard to read).
    ax.yaxis.set_major_locator(FixedLocator([0.2, 0.5, 1, 2, 5]))
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("κ = k*/k_c")
    ax.set_ylabel("contact resonance frequency (MHz)")
    ax.set_title(f"(a) lever: f₁ = 160 kHz, k_c = 40 N/m, r = {r}", loc="left", fontsize=10)
    handles = [
        plt.Line2D([], [], color="k", lw=1.8, label="contact resonance"),
        plt.Line2D([], [], color="k", ls="--", lw=0.9, label="free (κ = 0)"),
        plt.Line2D([], [], color="k", ls="-.", lw=0.9, label="pinned (κ → ∞)"),
    ]
    # Below the axes: a legend inside would sit on a curve somewhere over six decades of κ.
    ax.legend(
        handles=handles,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.16),
        ncol=3,
        frameon=False,
        fontsize=8,
    )


def map_panel(fig, ax, truth, result) -> dict[str, float]:
    x = result["x_m"].to_numpy(float) * 1e6  # extra columns stay text in the checked table
    y = result["y_m"].to_numpy(float) * 1e6
    nx, ny = np.unique(x).size, np.unique(y).size
    m = result["M_sample_Pa"].to_numpy().reshape(ny, nx) / 1e9
    step = x[1] - x[0]
    extent = (x.min() - step / 2, x.max() + step / 2, y.min() - step / 2, y.max() + step / 2)
    im = ax.imshow(m, origin="lower", extent=extent, cmap="viridis", interpolation="nearest")
    fig.colorbar(im, ax=ax, label="M_sample (GPa)", fraction=0.046, pad=0.03)
    recovered = {}
    for g, normal in enumerate(NAMED_SURFACES):
        cell = truth["grain"].to_numpy() == g
        label = "(" + "".join(map(str, normal)) + ")"
        value = float(np.median(result["M_sample_Pa"].to_numpy()[cell]) / 1e9)
        recovered[label] = value
        ax.annotate(
            f"{label}\n{value:.1f} GPa",
            (x[cell].mean(), y[cell].mean()),
            ha="center",
            va="center",
            fontsize=8,
            color="w",
            bbox=dict(boxstyle="round,pad=0.2", fc="k", alpha=0.45, lw=0),
        )
    ax.set_xlabel("x (µm)")
    ax.set_ylabel("y (µm)")
    ax.set_title("(b) Cu, inverted M_sample, noise 50 Hz", loc="left", fontsize=10)
    return recovered


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", type=Path, default=OUT)
    args = parser.parse_args(argv)
    plt.rcParams.update({"font.size": 9, "svg.hashsalt": "contactres"})
    _, truth, result = inverted_map()
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(10.5, 4.3), layout="constrained")
    frequency_panel(ax_a, truth["kappa"].to_numpy())
    recovered = map_panel(fig, ax_b, truth, result)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=130, metadata={"Software": None})
    plt.close(fig)
    true_m = truth.groupby("grain")["M_sample_Pa"].first()
    for g, (label, value) in enumerate(recovered.items()):
        print(f"{label}: M_sample {value:.1f} GPa (truth {true_m[g] / 1e9:.1f} GPa)")
    err = np.abs(result["M_sample_Pa"] / truth["M_sample_Pa"] - 1.0)
    print(f"max |M/M_true - 1| over the map: {err.max():.2g}; wrote {args.out}")


if __name__ == "__main__":
    main()
