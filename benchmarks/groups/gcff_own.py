"""GCFF's energy as GCFF's own code reaches it, beside the service's: the authors' MATLAB
(franzsetti/GCFF, MIT: ``gc.m`` and its alpha-expansion ``graphopt/expand.cpp``), run
unchanged under GNU Octave on every annotated frame of the shared sequences with each
sequence's own tuned parameters (its ``settings_gc.mat``: one stride, one cost per group),
and the service's grouping (``groups.detect_centres``: each round's assignment at its
lowest, the centres refitted between rounds as GCFF refits them) on the same people with
the same parameters, so both minimise one energy.

    python -m benchmarks.groups.gcff_own --gcff DIR [--out F]

``DIR``: a checkout of https://github.com/franzsetti/GCFF (measured at da29a12). Needs
``octave`` and ``mkoctfile`` (Debian: ``octave liboctave-dev octave-statistics``, the
last for ``pdist2``); the mex is compiled from the checkout's sources into a temporary
folder, nothing is written into it.

Per sequence: the frames where the service's grouping ends at a lower energy than GCFF's,
the same, a higher, and the difference summed over frames (m²; GCFF's cm² times 1e-4);
and F1 frame by frame (T = 2/3) of both, scored alike: GCFF's own figure for its tuned
set (``GCFF_TUNED``) is what its labels must reproduce, a check that this is GCFF's run.
Both stop where a round changes nothing (the centres refitted, the assignment again):
an assignment each round at its lowest can still settle elsewhere than alpha-expansion's,
lower or higher; the rounds' end is a local optimum for both.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from facing_service.core.social.groups import GroupParams, detect

from .. import results_file
from .exact import energy, found
from .held_out import gcff_params
from .scoring import f1
from .sequence_frame import Frame
from .sequences import CM, GCFF_TUNED, SEQUENCES, SHARED, load

CM2 = CM * CM
#: Reads frames (a header ``stride mdl n``, then n rows ``id x y theta``, cm and radians)
#: and writes each frame's labels from GCFF's ``gc`` as one line, then ``END``: Octave
#: 7.3 exits with status 1 after a mex has run ("ignoring const execution_exception
#: while preparing to exit"), so the last line, not the status, says the run finished.
DRIVER = """
fin = fopen('{inp}'); fout = fopen('{out}', 'w');
while true
  h = fscanf(fin, '%f', 3);
  if numel(h) < 3, break; end
  f = fscanf(fin, '%f', [4, h(3)])';
  if h(3) > 0, fprintf(fout, '%d ', gc(f, h(1), h(2))); end
  fprintf(fout, '\\n');
end
fprintf(fout, 'END\\n'); fclose(fin); fclose(fout);
"""


def tuned(sequence: str, root: Path = SHARED) -> tuple[float, float]:
    """The sequence's own GCFF parameters: stride (cm) and cost per group (cm²)."""
    from scipy.io import loadmat  # MATLAB v5 files, as sequences.load reads them

    settings = loadmat(root / sequence / "settings_gc.mat")
    return float(np.ravel(settings["stride"])[0]), float(np.ravel(settings["mdl"])[0])


def frames_text(frames: Sequence[Frame], stride_cm: float, mdl_cm2: float) -> str:
    """``frames`` as the driver reads them, back in GCFF's centimetres."""
    lines = []
    for f in frames:
        lines.append(f"{stride_cm!r} {mdl_cm2!r} {len(f.ids)}")
        lines += [f"{i} {x / CM!r} {y / CM!r} {t!r}"
                  for i, (x, y), t in zip(f.ids, f.positions.tolist(), f.headings.tolist(),
                                          strict=True)]  # fmt: skip
    return "\n".join(lines) + "\n"


def labels_read(text: str, frames: Sequence[Frame], why: str = "") -> list[np.ndarray]:
    """One labelling per frame from the driver's output, checked against the frames;
    ``why``: what Octave printed, said when the run ended early."""
    rows = text.split("\n")
    if rows[len(frames) : len(frames) + 1] != ["END"]:
        said = f": {why.strip()[-400:]}" if why.strip() else ""
        raise SystemExit(
            f"gcff_own: GCFF's run ended after {len(rows) - 1} of {len(frames)} frames{said}"
        )
    out = [np.array(row.split(), dtype=np.int64) for row in rows[: len(frames)]]
    if any(len(lab) != len(f.ids) for lab, f in zip(out, frames, strict=True)):
        raise SystemExit("gcff_own: GCFF's run did not label every person of every frame")
    return out


@contextmanager
def compiled(gcff: Path) -> Iterator[Path]:
    """A temporary folder holding GCFF's alpha-expansion mex, compiled once from the
    checkout's sources (nothing is written into the checkout)."""
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for source in (gcff / "graphopt").iterdir():
            if source.suffix in {".cpp", ".h"}:
                shutil.copy(source, work)
        subprocess.run(["mkoctfile", "--mex", "-O3", "expand.cpp", "-o", "expand.mex"],
                       cwd=work, check=True, capture_output=True)  # fmt: skip
        yield work


def gcff_labels(
    gcff: Path, mex: Path, frames: Sequence[Frame], stride_cm: float, mdl_cm2: float
) -> list[np.ndarray]:
    """GCFF's own labels of every frame: its ``gc`` run under Octave, the mex from ``mex``."""
    (mex / "in.txt").write_text(frames_text(frames, stride_cm, mdl_cm2))
    out = mex / "out.txt"
    out.unlink(missing_ok=True)  # the last sequence's
    script = DRIVER.format(inp=mex / "in.txt", out=out)
    setup = f"pkg load statistics; addpath('{gcff}'); addpath('{mex}');"
    run = subprocess.run(["octave", "--no-gui", "--quiet", "--eval", setup + script],
                         cwd=mex, capture_output=True, text=True)  # fmt: skip
    return labels_read(out.read_text() if out.is_file() else "", frames, run.stderr)


def compared(sequence: str, gcff: Path, mex: Path) -> dict[str, Any]:
    """GCFF's run and the service's on one sequence, at the sequence's tuned parameters."""
    frames = load(sequence)
    stride_cm, mdl_cm2 = tuned(sequence)
    p: GroupParams = gcff_params(stride_cm * CM, mdl_cm2 * CM2)
    theirs = gcff_labels(gcff, mex, frames, stride_cm, mdl_cm2)
    ours = [detect(f.positions, f.headings, p) for f in frames]
    e_theirs = np.array([energy(f, lab, p) for f, lab in zip(frames, theirs, strict=True)])
    e_ours = np.array([energy(f, lab, p) for f, lab in zip(frames, ours, strict=True)])
    same = np.isclose(e_ours, e_theirs, rtol=1e-9, atol=1e-9)

    def score(labels: list[np.ndarray]) -> float:
        return f1(frames, [found(f, lab) for f, lab in zip(frames, labels, strict=True)], 2 / 3)

    return {
        "frames": len(frames),
        "stride_cm": stride_cm,
        "mdl_cm2": mdl_cm2,
        "lower": int((~same & (e_ours < e_theirs)).sum()),
        "same": int(same.sum()),
        "higher": int((~same & (e_ours > e_theirs)).sum()),
        # summed over frames, not each total: a hidden member's penalty (up to 1e8 m²)
        # would swamp them, where it is the same on both sides
        "difference_m2": float((e_ours - e_theirs).sum()),
        "f1": {
            "gcff": score(theirs),
            "service": score(ours),
            "gcff_published": GCFF_TUNED[sequence],
        },
    }


def tables(results: dict[str, Any]) -> list[str]:
    lines = [
        "sequence | frames | stride cm, mdl cm² | the service's energy lower / same / higher "
        "| service - GCFF, m² over frames | F1 GCFF (its figure) / service"
    ]
    for s, r in results["sequences"].items():
        f = r["f1"]
        lines.append(
            f"{s} | {r['frames']} | {r['stride_cm']:g}, {r['mdl_cm2']:g} | "
            f"{r['lower']} / {r['same']} / {r['higher']} | {r['difference_m2']:+.2f} | "
            f"{f['gcff']:.3f} ({f['gcff_published']:.2f}) / {f['service']:.3f}"
        )
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gcff", type=Path, required=True, help="a checkout of GCFF")
    parser.add_argument("--out", type=Path, help="write the results as JSON")
    args = parser.parse_args(argv)
    if not (args.gcff / "gc.m").is_file() or not (args.gcff / "graphopt/expand.cpp").is_file():
        parser.error(f"--gcff {args.gcff}: not a GCFF checkout (no gc.m, graphopt/expand.cpp)")
    for tool in ("octave", "mkoctfile"):
        if shutil.which(tool) is None:
            parser.error(f"--gcff needs {tool} (Debian: octave liboctave-dev octave-statistics)")
    commit = subprocess.run(["git", "-C", str(args.gcff), "rev-parse", "HEAD"],
                            capture_output=True, text=True).stdout.strip()  # fmt: skip
    gcff = args.gcff.resolve()
    with compiled(gcff) as mex:
        results = {
            "gcff_commit": commit or None,  # None: not a git checkout
            "sequences": {s: compared(s, gcff, mex) for s in SEQUENCES},
        }
    command = "python -m benchmarks.groups.gcff_own"
    return results_file.report(tables(results), results, args.out, command, vars(args))


if __name__ == "__main__":
    raise SystemExit(main())
