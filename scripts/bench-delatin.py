"""pydelatin's one-level greedy TIN of the bundled geographic DEM (no
nodata: pydelatin takes every pixel as a height), 2 m and 5 m, error at
the pixel centres only: wall time (median of 3) and triangles, the table
`make bench` prints beside `cargo bench --bench engine` (issue 74,
scripts/bench-engine.sh). A second argument k makes each pixel k x k
pixels first (terraces, one run each). The GeoTIFF is read by `tifffile` (in the
project's venv, scripts/setup.sh), else by GDAL's Python bindings."""
import statistics
import sys
import time

import numpy as np
from pydelatin import Delatin


def read(path):
    try:
        import tifffile
        return tifffile.imread(path).astype(np.float64)
    except ImportError:
        from osgeo import gdal
        return gdal.Open(path).ReadAsArray().astype(np.float64)


def main():
    z = read(sys.argv[1])
    # an optional factor k: each pixel made k x k pixels (terraces)
    k = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    if k > 1:
        z = np.repeat(np.repeat(z, k, axis=0), k, axis=1)
    h, w = z.shape
    print("| DEM | pixels | tolerance | pydelatin ms (median of 3) | triangles | vertices |")
    print("|---|---:|---:|---:|---:|---:|")
    for tol in (2.0, 5.0):
        times = []
        for _ in range(3 if k == 1 else 1):
            t0 = time.perf_counter()
            tin = Delatin(z, width=w, height=h, max_error=tol)
            times.append((time.perf_counter() - t0) * 1e3)
        name = sys.argv[1].rsplit('/', 1)[-1] + (f" x{k}" if k > 1 else "")
        print(f"| {name} | {w * h} | {tol:g} | {statistics.median(times):.0f} "
              f"| {len(tin.triangles)} | {len(tin.vertices)} |")


main()
