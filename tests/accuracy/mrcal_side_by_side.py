#!/usr/bin/python3
"""monocle and mrcal (the field's reference, Debian's python3-mrcal) on the same corners.

`monocle intrinsics calibrate --corners` writes the corners it used (mrcal's corners.vnl);
mrcal's calibration tool fits the same lens model to them (a flat board, no regularization,
no outlier rejection: the corners monocle left out are marked missing). Both
tools' intrinsics and projection uncertainty are printed together. Fails if fx fy cx cy or a
distortion term of monocle leaves mrcal's by more than their combined 1 sigma, or if
monocle's analytic (Gauss-Newton) 1 sigma is not mrcal's to 5 %.

  mrcal_side_by_side.py MONOCLE IMAGE_DIR WORK_DIR [CAMERA ...]   (default: left right)
"""
import json
import subprocess
import sys
from pathlib import Path

try:
    import numpy as np
    import mrcal
except ImportError as e:
    sys.exit(f"mrcal_side_by_side: {e}: install python3-mrcal (scripts/setup does)")

SPACING_M = 0.025
BOARD_COLS, BOARD_ROWS = 9, 6


def run_monocle(monocle, images, work):
    out = subprocess.run(
        [monocle, "intrinsics", "calibrate", *map(str, images), "--board", "9x6", "--square",
         str(SPACING_M), "--model", "k1k2p1p2", "--out", str(work / "cal.pbtxt"), "--corners",
         str(work / "corners.vnl"), "--json"], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def run_mrcal(work, imagersize, camera):
    """mrcal's own calibration tool on monocle's corners, as its users run it: the same lens
    model, a flat board, no regularization and no outlier rejection (monocle's blunders are
    already marked missing)."""
    out = subprocess.run(
        ["mrcal-calibrate-cameras", "--corners-cache", str(work / "corners.vnl"), "--lensmodel",
         "LENSMODEL_OPENCV4", "--focal", "530", "--object-spacing", str(SPACING_M),
         "--object-width-n", str(BOARD_COLS), "--object-height-n", str(BOARD_ROWS),
         "--imagersize", str(imagersize[0]), str(imagersize[1]), "--skip-regularization",
         "--skip-outlier-rejection", "--skip-calobject-warp-solve", "--outdir", str(work),
         f"{camera}*.jpg"], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("mrcal-calibrate-cameras failed:\n" + out.stdout + out.stderr)
    return mrcal.cameramodel(str(work / "camera-0.cameramodel"))


def intrinsics_sigma(inputs):
    """The Gauss-Newton 1 sigma of the intrinsics, noise from the residuals."""
    packed, x, jacobian, _ = mrcal.optimizer_callback(**inputs)
    j = jacobian.toarray()
    used = inputs["observations_board"][..., 2] > 0
    measurements = 2 * int(used.sum())
    variance = float((x[:measurements] ** 2).sum()) / (measurements - j.shape[1])
    covariance_packed = variance * np.linalg.inv(j.T @ j)
    scale = np.ones(len(packed))
    mrcal.unpack_state(scale, **inputs)  # in place: the packed state's scale
    nk = inputs["intrinsics"].shape[1]
    return np.sqrt(np.diag(covariance_packed)[:nk]) * scale[:nk]


def compare(monocle, images, work, camera):
    """Prints both tools' figures; returns what failed."""
    work.mkdir(parents=True, exist_ok=True)
    ours = run_monocle(monocle, images, work)
    model = run_mrcal(work, (ours["width"], ours["height"]), camera)
    inputs = model.optimization_inputs()
    theirs = model.intrinsics()[1]
    their_sigma = intrinsics_sigma(inputs)
    s = ours["sigma"]
    analytic = ours["analytic_sigma"]
    my_analytic = [analytic["fx"], analytic["fy"], analytic["cx"], analytic["cy"],
                   *analytic["distortion"][:4]]
    mine = [ours["fx"], ours["fy"], ours["cx"], ours["cy"], *ours["distortion"][:4]]
    my_sigma = [s["fx"], s["fy"], s["cx"], s["cy"], *s["distortion"][:4]]
    print(f"{camera}: {len(inputs['observations_board'])} views, k1k2p1p2 (mrcal: "
          f"LENSMODEL_OPENCV4); RMS of a corner's distance: monocle {ours['rms_px']:.4f} px")
    print(f"{'':4}{'monocle':>14} {'1 sigma':>10} {'analytic':>10} {'mrcal':>14} "
          f"{'1 sigma':>10} {'z':>7}")
    failures = []
    for name, a, sa, aa, b, sb in zip(["fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"], mine,
                                      my_sigma, my_analytic, theirs, their_sigma):
        z = (a - b) / np.hypot(sa, sb)
        print(f"{name:4}{a:14.6g} {sa:10.3g} {aa:10.3g} {b:14.6g} {sb:10.3g} {z:7.3f}")
        if not abs(z) <= 1:
            failures.append(f"{name}: monocle {a:.6g} and mrcal {b:.6g} differ by {z:.2f} "
                            "combined sigma")
        # The same Gauss-Newton covariance, computed by each tool from its own Jacobian.
        if not abs(aa - sb) <= 0.05 * sb:
            failures.append(f"{name}: monocle's analytic 1 sigma {aa:.3g} is not mrcal's {sb:.3g}")
    # Projection uncertainty of a ray (at infinity), worst direction, at a few pixels.
    width, height = ours["width"], ours["height"]
    rel, absolute = ours["relative_projection_sigma"], ours["projection_sigma"]
    probes = {"centre": (width / 2, height / 2), "(20, 20)": (20, 20),
              "monocle's worst": (rel["worst_x"], rel["worst_y"])}
    print("projection 1 sigma (px, worst direction):  mrcal (its board-frame method)")
    for label, q in probes.items():
        v = mrcal.unproject(np.array(q, dtype=float), *model.intrinsics())
        sigma = mrcal.projection_uncertainty(v, model, atinfinity=True,
                                             what="worstdirection-stdev")
        print(f"  {label:16} at ({q[0]:.0f}, {q[1]:.0f}): {float(sigma):.3f}")
    print(f"  monocle, best camera rotation out: centre {rel['centre_px']:.3f}, median "
          f"{rel['median_px']:.3f}, worst {rel['worst_px']:.3f} at ({rel['worst_x']:.0f}, "
          f"{rel['worst_y']:.0f}); a ray fixed in the camera: centre {absolute['centre_px']:.3f}, "
          f"median {absolute['median_px']:.3f}")
    return [f"{camera}: {f}" for f in failures]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    monocle, image_dir, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    failures = []
    for camera in sys.argv[4:] or ["left", "right"]:
        images = sorted(image_dir.glob(f"{camera}[0-9][0-9].jpg"))
        if not images:
            print(f"mrcal_side_by_side: no {camera}NN.jpg in {image_dir}: install opencv-doc "
                  "(scripts/setup does); skipped")
            return 77
        failures += compare(monocle, images, work / camera, camera)
    for f in failures:
        print("FAIL " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
