#!/usr/bin/python3
"""ParaView files read back through VTK's own readers (lib/scene/vtk_output.hpp).

Three short runs with [output] vtk = true — one cell (also stopped and resumed: the same files),
one rigid disk, two obstacles — then every
dataset of run.pvd is opened with vtkXMLImageDataReader / vtkXMLPolyDataReader: array names and
sizes, its time against the collection's, and one value against series.csv (the largest speed,
cell 0's centroid, disk 0's centre). The .pvd itself is plain XML (no VTK reader of it in VTK 9.1's
Python): read with xml.etree.

usage: vtk_readback.py RBCFLOW_BINARY WORK_DIR          (Debian's python3-vtk9: make deps)
"""
import csv
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

try:
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPolyDataReader
except ImportError as e:
    sys.exit(f"vtk_readback: VTK's Python modules are missing ({e}); install Debian's python3-vtk9 (make deps)")

CHANNEL = """[channel]
length = {L}
height = 10e-6
mesh_size = 0.625e-6
reynolds = 0.5556
[time]
dt = 1e-6
end = 1e-4
coupling = "semi-implicit"
[output]
every = 1e-5
vtk = true
vtk_every = 2e-5
"""
SCENES = {
    "cell": CHANNEL.format(L="20e-6") + "[[cell]]\ncenter = [19e-6, 4e-6]\nswelling_ratio = 0.7\n",
    "disk": CHANNEL.format(L="20e-6") + "[[disk]]\ncenter = [10e-6, 4e-6]\nradius = 1.25e-6\n",
    "obstacles": CHANNEL.format(L="40e-6")
    + "[[obstacle]]\nx = [15e-6, 25e-6]\ny = [0.0, 2.5e-6]\nwall = \"bottom\"\n"
    + "[[obstacle]]\nx = [15e-6, 25e-6]\ny = [7.5e-6, 10e-6]\nwall = \"top\"\n",
}
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def read(path):
    reader = vtkXMLImageDataReader() if path.endswith(".vti") else vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    check(reader.GetErrorCode() == 0, f"{path}: VTK's reader reports error {reader.GetErrorCode()}")
    return reader.GetOutput()


def tuples(a):
    return [a.GetTuple(k) for k in range(a.GetNumberOfTuples())]


def array(data, name, where="point"):
    a = (data.GetPointData() if where == "point" else data.GetCellData()).GetArray(name)
    check(a is not None, f"array '{name}' missing ({where} data)")
    return tuples(a) if a is not None else None


def series_row(out, t):
    with open(os.path.join(out, "series.csv")) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))  # (the units line)
    row = min(rows, key=lambda r: abs(float(r["t"]) - t))
    check(abs(float(row["t"]) - t) < 1e-9, f"series.csv has no sample at t = {t}")
    return row


def polygon_centroid(x, y):
    a = cx = cy = 0.0
    for k in range(len(x)):
        j = (k + 1) % len(x)
        c = x[k] * y[j] - x[j] * y[k]
        a += c
        cx += (x[k] + x[j]) * c
        cy += (y[k] + y[j]) * c
    return cx / (3 * a), cy / (3 * a)


def main():
    binary, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    for name, text in SCENES.items():
        scene = os.path.join(work, name + ".toml")
        with open(scene, "w") as f:
            f.write(text)
        out = os.path.join(work, name)
        subprocess.run([binary, "run", scene, "--out", out, "--threads", "1", "--quiet"], check=True)
        vtk_dir = os.path.join(out, "vtk")
        entries = ET.parse(os.path.join(vtk_dir, "run.pvd")).getroot().find("Collection").findall("DataSet")
        flows = [e for e in entries if e.get("part") == "0"]
        times = [float(e.get("timestep")) for e in flows]
        check(len(flows) == 6, f"{name}: {len(flows)} fluid samples in run.pvd, expected 6 (0 to 100 us every 20 us)")
        check(all(abs(t - 2e-5 * k) < 1e-9 for k, t in enumerate(times)), f"{name}: sample times {times}")
        for e in entries:
            data = read(os.path.join(vtk_dir, e.get("file")))
            t = float(e.get("timestep"))
            time_value = data.GetFieldData().GetArray("TimeValue")
            check(time_value is not None and (e.get("file") == "obstacles.vtp" or abs(time_value.GetValue(0) - t) < 1e-15),
                  f"{name}: {e.get('file')} TimeValue against the collection's {t}")
            part = e.get("part")
            if part == "0":
                L = 20e-6 if name != "obstacles" else 40e-6
                nx, ny = round(L / 0.625e-6), 16
                dims = data.GetDimensions()
                check(dims == (nx + 1, ny + 1, 1), f"{name}: image dimensions {dims}")
                u = array(data, "velocity [m/s]")
                check(u is not None and len(u) == (nx + 1) * (ny + 1) and len(u[0]) == 3, f"{name}: velocity shape")
                array(data, "pressure [Pa]")
                array(data, "vorticity [1/s]")
                if u is not None and t > 0:
                    speed = max(math.hypot(a, b) for a, b, _ in u)
                    ref = float(series_row(out, t)["max_speed"])
                    check(abs(speed - ref) <= 1e-8 * ref, f"{name}: largest speed {speed} against series.csv {ref} at t = {t}")
            elif part == "1":
                check(data.GetNumberOfLines() == 1, f"{name}: {data.GetNumberOfLines()} membrane lines")
                ids = array(data, "cell_id")
                array(data, "force [N/m]")
                array(data, "stretch")
                pts = tuples(data.GetPoints().GetData())
                check(ids is not None and len(pts) == 76 and len(ids) == 76, f"{name}: {len(pts)} membrane nodes")
                cx, cy = polygon_centroid([p[0] for p in pts], [p[1] for p in pts])
                row = series_row(out, t)
                sx = float(row["cell0_x"]) % 20e-6
                check(abs(cx - sx) < 1e-12 and abs(cy - float(row["cell0_y"])) < 1e-12,
                      f"{name}: cell 0's centroid ({cx}, {cy}) against series.csv ({sx}, {row['cell0_y']}) at t = {t}")
            elif part == "2":
                pts = tuples(data.GetPoints().GetData())
                array(data, "disk_id")
                array(data, "velocity [m/s]")
                array(data, "angular_velocity [1/s]")
                r = array(data, "radius [m]")
                check(len(pts) == 65 and data.GetNumberOfLines() == 2, f"{name}: {len(pts)} disk points, {data.GetNumberOfLines()} lines")
                row = series_row(out, t)
                gx, gy = pts[64][0], pts[64][1]  # the centre (the radius line's first point)
                check(abs(gx - float(row["disk0_x"]) % 20e-6) < 1e-12 and abs(gy - float(row["disk0_y"])) < 1e-12,
                      f"{name}: disk centre ({gx}, {gy}) against series.csv at t = {t}")
                check(r is not None and abs(r[0][0] - 1.25e-6) < 1e-18, f"{name}: disk radius")
            elif part == "3":
                check(data.GetNumberOfPolys() == 2, f"{name}: {data.GetNumberOfPolys()} obstacles")
                b = data.GetBounds()
                check(abs(b[0] - 15e-6) < 1e-18 and abs(b[1] - 25e-6) < 1e-18 and b[2] == 0 and abs(b[3] - 10e-6) < 1e-18,
                      f"{name}: obstacle bounds {b}")
        if name == "cell":
            # Stopped after its checkpoint at 90 us and resumed: the same collection and files.
            again = os.path.join(work, "cell_resumed")
            subprocess.run([binary, "run", scene, "--out", again, "--threads", "1", "--quiet", "--checkpoint-sim", "3e-5"], check=True)
            os.remove(os.path.join(again, "summary.json"))
            subprocess.run([binary, "resume", again, "--threads", "1", "--quiet"], check=True)
            for f in ["run.pvd", "flow_00005.vti", "membranes_00005.vtp"]:
                with open(os.path.join(vtk_dir, f), "rb") as a, open(os.path.join(again, "vtk", f), "rb") as b:
                    check(a.read() == b.read(), f"{name}: {f} of the resumed run differs from the straight run's")
        parts = {e.get("part") for e in entries}
        expected = {"cell": {"0", "1"}, "disk": {"0", "2"}, "obstacles": {"0", "3"}}[name]
        check(parts == expected, f"{name}: parts {sorted(parts)} in run.pvd, expected {sorted(expected)}")
    if failures:
        sys.exit(f"vtk_readback: {len(failures)} failures")
    print("vtk_readback: every dataset read back through VTK's readers")


if __name__ == "__main__":
    main()
