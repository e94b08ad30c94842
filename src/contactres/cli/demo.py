"""CLI: ``contactres demo``: the main job on the bundled example data."""

from __future__ import annotations

import click

from ._app import main


@main.command()
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default="contactres-demo",
    show_default=True,
    help="Folder to write the results into (created if missing).",
)
def demo(out: str) -> None:
    """Run the main job on the bundled example data and write its results into OUT.

    Takes 10-30 s; a line per step on stderr.

    \b
    Example: contactres demo --out contactres-demo
    """
    from ..apps import check_demo_output, write_demo
    from ..jobs import demo as job
    from ..report import friction_table

    # Refused before the work: a path that cannot be the folder, a file of the user's under one
    # of the demo's names (issue 27: never overwritten); nothing is changed then.
    check_demo_output(out)
    progress = lambda title: click.echo(f"  - {title}", err=True)  # noqa: E731
    result = job.run(None, job.Settings(), progress)
    written = write_demo(result, out)
    for line in result.warnings:
        click.echo(f"contactres demo: {line}", err=True)
    click.echo(f"wrote {len(written)} files into {out}/")
    # Then the numbers a user came for, last on the screen: Table 1 (E and γ per group, with
    # the analysis' counts), μ per load, and the modulus map's statistics when that step ran.
    click.echo("\nTable 1 (paper 2): E and γ of every configuration and medium")
    click.echo(_results_lines(result.sweeps_analysis))
    click.echo("\nfriction coefficient per load (exact-loop fit, median over experiments)")
    click.echo(friction_table(result.sweeps_analysis).to_string(index=False))
    click.echo("\nthe same chain from the bundled admittance spectra (qcm-spectra/)")
    click.echo(_results_lines(result.spectra_analysis))
    if result.map_dataset is not None:
        click.echo("\n" + _map_line(result.map_dataset["M_Pa"].values))
    if result.map_fit is not None:
        click.echo(_fit_line(result.map_fit["flat"]))
    if result.cr_map is not None:
        click.echo(_cr_map_line(result.cr_map.summary))


def _results_lines(results) -> str:
    """The analysis' repr without its last line (the Python hint, not a number)."""
    return "\n".join(repr(results).splitlines()[:-1])


def _map_line(M) -> str:
    """The predicted modulus map's statistics: pixels, M range and median (GPa)."""
    import numpy as np

    finite = M[np.isfinite(M)]
    return (
        f"polycrystal map: {finite.size} pixels, M from {finite.min() / 1e9:.4g} to "
        f"{finite.max() / 1e9:.4g} GPa, median {np.median(finite) / 1e9:.4g} GPa"
    )


def _fit_line(flat: dict) -> str:
    """What the bundled k* map determines of Cu's constants: the strong combination of the
    ratios and M(111)/M(001) (a map of stiffness ratios leaves the weak combination, and so the
    ratios one by one, undetermined: said, not printed as values)."""
    line = "constants fitted back from the k* map"
    if flat.get("strong_identified") and flat.get("strong_combination") is not None:
        line += (
            f": strong combination {flat['strong_combination']:.4g} "
            f"(rel. error {flat['strong_error']:.2g})"
        )
    if flat.get("anisotropy_111") is not None:
        line += (
            f", M(111)/M(001) = {flat['anisotropy_111']:.4g} ± {flat['anisotropy_111_error']:.2g}"
        )
    if not flat.get("weak_identified"):
        line += (
            "\n  (C12/C11 and C44/C11 one by one: not determined by this map; polycrystal/fit.json)"
        )
    return line


def _cr_map_line(summary: dict) -> str:
    """The CR-AFM map's medians (k*, M, tan δ) and its pixel counts."""
    line = f"CR-AFM map (cr-map/): {summary['pixels_with_k_star']} pixels with k*"
    if summary.get("median_k_star_N_per_m") is not None:
        line += f", median k* {summary['median_k_star_N_per_m']:.4g} N/m"
    if summary.get("median_M_Pa") is not None:
        line += f", M {summary['median_M_Pa'] / 1e9:.4g} GPa"
    if summary.get("median_tan_delta") is not None:
        line += f", tan δ {summary['median_tan_delta']:.3g}"
    return line + f"; {summary['pixels_flagged']} flagged"
