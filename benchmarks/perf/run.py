"""One benchmark run: the bare relays and the real service, fed by the same driver.

    python -m benchmarks                  # full sizes (about 20 minutes)
    python -m benchmarks --quick          # small; what CI runs so this never rots
    python -m benchmarks --cells client/publishers/results   # chosen cells only

The grid (``benchmarks.perf.grid``): for each tracker mode (peer, client), publishing style
(``Session.put``, declared publishers) and consumer (none, the per-body results,
everything), the three bare relays and the service, each: latency, a soak, a BLOCK
flood, the soak again. Every service figure is also a ratio to the cheapest relay for
that cell, measured in the same run (this machine is shared and noisy: ratios, not
absolute numbers, are the comparison). Then the ROS 2 path, fed as a robot feeds it,
against the JSON path fed the same way; then the detector core alone. Writes
benchmarks/results/latest.json.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import paths, results_file
from . import core, grid
from .report import CORE_SPEEDUP_MIN, PAGE, TARGETS, render, verdicts

RESULTS = paths.RESULTS / "latest.json"


def ros_ratios(json_path: dict, ros_path: dict) -> dict[str, float]:
    """The ROS 2 path against the JSON path of the same service: CPU per pose in the soak
    (both at the same rate), burst throughput and soak latency."""
    return {
        "ros_cpu_per_pose": ros_path["soak"]["us_per_pose"] / json_path["soak"]["us_per_pose"],
        "ros_burst_throughput": ros_path["burst"]["results_per_s"]
        / json_path["burst"]["results_per_s"],
        "ros_soak_p99": ros_path["soak"]["p99_ms"] / json_path["soak"]["p99_ms"],
    }


#: The JSON path the ROS 2 path is compared with: fed the same way, as a robot feeds it.
JSON_PATH = ("peer", "publishers", "results")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes, two cells, for CI")
    parser.add_argument("--cells", help="only these cells: mode/style/consumer,...")
    parser.add_argument("--warmup", type=int, default=200)
    parser.add_argument("--latency-n", type=int, default=1000)
    parser.add_argument("--burst-n", type=int, default=40_000)
    parser.add_argument("--soak-bodies", type=int, default=100)
    parser.add_argument("--soak-hz", type=float, default=30.0)
    parser.add_argument("--soak-s", type=float, default=6.0)
    parser.add_argument("--core-sizes", default="1,100,10000,1000000")
    parser.add_argument("--out", type=Path, default=RESULTS)
    parser.add_argument(
        "--before", type=Path, help="a source tree whose service is measured too, same run"
    )
    args = parser.parse_args()
    if args.quick:
        args.warmup, args.latency_n, args.burst_n, args.soak_s = 20, 50, 2000, 1.0
        args.soak_bodies, args.core_sizes = 20, "1,100,10000"
        args.cells = args.cells or "peer/put/none,client/publishers/results"
    chosen, sizes = grid.cells(args.cells), grid.Sizes.of(args)
    # the page quotes the machine and the parameters: kept at the top, as before, from the
    # same provenance results_file writes first
    said = results_file.provenance("python -m benchmarks", vars(args))
    report: dict = {
        "version": said["version"],
        "machine": said["machine"],
        "parameters": said["parameters"],
        "grid": grid.run(chosen, sizes, args.before),
    }
    measured = {grid.cell_of(c): c["targets"]["service"] for c in report["grid"]}
    json_path = measured.get(JSON_PATH) or grid.measure("service", JSON_PATH, sizes)
    report["service_json"] = json_path
    report["service_ros"] = grid.measure("service-ros", JSON_PATH, sizes)
    report["ros_ratios"] = ros_ratios(json_path, report["service_ros"])
    report["core"] = core.measure(
        tuple(int(n) for n in args.core_sizes.split(",")), min_time=0.05 if args.quick else 0.3
    )
    report["verdicts"] = verdicts(report)
    report["targets"] = TARGETS
    report["core_speedup_min"] = CORE_SPEEDUP_MIN
    results_file.write(args.out, report, "python -m benchmarks", vars(args))
    print(render(report))
    print(f"\nwritten to {args.out}; python -m benchmarks.perf.report puts it in {PAGE.name}")


if __name__ == "__main__":
    main()
