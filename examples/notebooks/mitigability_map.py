"""The mitigability map (the paper's Fig. "mitigability region", panel b) from Python.

Sweeps the fine speed x TTC grid of examples/tjunction/campaign.yaml with emrm.sweep (or reads a
results folder that has it) and draws each cell's region: G fully avoidable, Y aggressive
avoidance required, O mitigatable, R not mitigatable, grey infeasible. With matplotlib installed
(Debian: python3-matplotlib) it writes OUT/mitigability_map.png; without, OUT/mitigability_map.csv
and the map as letters on the terminal. docs/python.md walks through it.

    PYTHONPATH=build/release/python python3 examples/notebooks/mitigability_map.py --quick
    PYTHONPATH=build/release/python python3 examples/notebooks/mitigability_map.py --results out/campaign

--quick sweeps every third speed and TTC (about 220 cells, seconds); without it the whole fine grid
(1978 cells, about half a minute on two cores). A rerun into the same OUT resumes the sweep.
"""

import argparse
from pathlib import Path

import emrm

EXAMPLE = Path(__file__).resolve().parents[1] / "tjunction"
COLOURS = {"G": "#2ca02c", "Y": "#ffdd57", "O": "#ff7f0e", "R": "#d62728", "infeasible": "#bdbdbd"}  # the report's


def fine_grid(quick: bool) -> dict:
    """The fine grid of campaign.yaml, as a campaign of its own: the same name, factors and seed,
    so the same cells with the same seeds and results. --quick takes every third level."""
    every = 3 if quick else 1
    return {
        "scene": str(EXAMPLE / "scene.yaml"),
        "seed": 1,
        "grids": [{
            "name": "fine",
            "speed_kph": {"from": 30, "to": 72, "step": every},
            "ttc_s": {"from": 0.25, "to": 2.95, "step": round(0.06 * every, 2)},
            "mu": 1.0,
            "passage_m": 3.0,
        }],
    }


def region_map(regions):
    """Speed (rows) x TTC (columns) -> region, of the fine grid."""
    fine = regions[regions.grid == "fine"]
    return fine.pivot(index="speed_kph", columns="ttc_s", values="region").sort_index(ascending=False)


def draw(grid, path: Path) -> bool:
    """The map as a PNG, coloured as the report colours it; False without matplotlib."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.colors import ListedColormap
        from matplotlib.patches import Patch
    except ImportError:
        return False
    names = list(COLOURS)
    codes = grid.apply(lambda column: column.map(names.index))
    speeds, ttcs = grid.index.to_numpy(), grid.columns.to_numpy()
    half_speed = abs(speeds[0] - speeds[1]) / 2 if len(speeds) > 1 else 0.5  # each cell centred on its values
    half_ttc = (ttcs[1] - ttcs[0]) / 2 if len(ttcs) > 1 else 0.05
    figure, axes = plt.subplots(figsize=(8, 6))
    axes.imshow(codes.to_numpy(), cmap=ListedColormap(list(COLOURS.values())), vmin=0, vmax=len(names) - 1,
                aspect="auto", interpolation="nearest",
                extent=(ttcs[0] - half_ttc, ttcs[-1] + half_ttc, speeds[-1] - half_speed, speeds[0] + half_speed))
    axes.set_xlabel("time to collision (s)")
    axes.set_ylabel("ego speed (km/h)")
    axes.set_title("Mitigability map: speed x TTC, mu 1.0, passage 3.0 m")
    axes.legend(handles=[Patch(color=c, label=n) for n, c in COLOURS.items()], loc="upper right", fontsize="small")
    figure.savefig(path, dpi=120, bbox_inches="tight")
    return True


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/notebook"), help="results folder of the sweep")
    parser.add_argument("--results", type=Path, help="read this results folder instead of sweeping")
    parser.add_argument("--quick", action="store_true", help="every third speed and TTC only")
    parser.add_argument("--threads", type=int, default=0, help="0: every core")
    args = parser.parse_args()

    if args.results:
        results = emrm.load_results(args.results)
        out = args.results
    else:
        out = args.out / ("fine-quick" if args.quick else "fine")
        results = emrm.sweep(fine_grid(args.quick), out, threads=args.threads)
        print(f"{results.summary['cells_simulated']} cells simulated, {results.summary['cells_done_before']} "
              f"already stored, {results.summary['seconds']:.1f} s")
    grid = region_map(results.regions)
    counts = results.regions[results.regions.grid == "fine"].region.value_counts()
    print("regions:", ", ".join(f"{name} {counts.get(name, 0)}" for name in COLOURS))
    if draw(grid, out / "mitigability_map.png"):
        print(f"wrote {out / 'mitigability_map.png'}")
        return
    grid.to_csv(out / "mitigability_map.csv")
    print(f"matplotlib is not installed: wrote {out / 'mitigability_map.csv'}; the map (rows: speed, "
          "columns: TTC rising; . infeasible):")
    for speed, row in grid.iterrows():
        print(f"{speed:5.0f} " + "".join("." if r == "infeasible" else r for r in row))


if __name__ == "__main__":
    main()
