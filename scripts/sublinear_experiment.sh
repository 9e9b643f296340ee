#!/usr/bin/env bash
# The sub-linear experiment of paper 002 (Sec. 6.3, App. B): fields of 1, 4, 16, 64 and 256
# copies of a tree stretching away from a fixed viewer, the colour-cube octree one level
# deeper each time the field quadruples; brute force and colorcube benched on each, and one
# plot of frame time and drawn triangles against scene size.
#
#   scripts/sublinear_experiment.sh TREE.ffscene OUT_DIR [FRAMES] [BASE_DEPTH] [SPACING]
#
# SPACING is in tree widths (default 4); BASE_DEPTH (default 7) is the octree depth of one
# spacing, so a leaf cube is spacing / 2^BASE_DEPTH / 4 and the front tree stands where such a
# cube is one pixel, plus one spacing. With the defaults the 256-tree field (13.4M triangles)
# bakes at depth 11 and needs ~12 GB; the dense field of the first measurements is
# `... 30 4 1.5`. Extra colorcube settings for both: COLORCUBE_SETTINGS="--set colorcube.
# occlusion=0 --set colorcube.inner_faces=keep" benches paper 002's own walk.
set -euo pipefail
usage="usage: $0 TREE.ffscene OUT_DIR [FRAMES] [BASE_DEPTH] [SPACING]"
tree=${1:?$usage}
out=${2:?$usage}
frames=${3:-30}
base_depth=${4:-7}
spacing_widths=${5:-4}
farfield=${FARFIELD:-$(dirname "$0")/../build/farfield}
mkdir -p "$out"

width=$("$farfield" info "$tree" | awk '/^size:/ { print ($2 > $6 ? $2 : $6) }')
spacing=$(awk -v w="$width" -v k="$spacing_widths" 'BEGIN { printf "%.2f", k * w }')
height=$("$farfield" info "$tree" | awk '/^size:/ { print $4 }')

depth=$base_depth
for count in 1 4 16 64 256; do
  field="$out/field_$count.ffscene"
  "$farfield" generate field --mesh "$tree" --count "$count" --spacing "$spacing" --out "$field" -q
  # The viewer looks across the field at 25 degrees to the octree axes (paper 002, Plate 1)
  # from where the front tree is drawn with the octree's leaf cubes (Sec. 6.3): the distance
  # at which a leaf cube (spacing / 2^base_depth / cluster, the same for every field since the
  # octree deepens as the field grows) shrinks to one pixel at 1024 pixels across 90 degrees.
  /usr/bin/python3 - "$field" "$out/path_$count.json" "$frames" "$spacing" "$height" "$base_depth" <<'PY'
import json, math, sys
field, path, frames, spacing, height, base = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6])
count = int(field.rsplit("_", 1)[1].split(".")[0])
n = math.ceil(math.sqrt(count))
first = -0.5 * spacing * (n - 1)  # generate field centres the grid on the origin
cube = spacing / 2 ** base / 4
distance = cube / (2 * math.tan(math.radians(45)) / 1024) + spacing
yaw = 25.0
x = first - distance * math.cos(math.radians(yaw))
z = first - distance * math.sin(math.radians(yaw))
poses = [{"position": [x + 0.05 * i, 0.6 * height, z], "yaw_deg": yaw, "pitch_deg": -2.0} for i in range(frames)]
json.dump({"format": "farfield-path", "version": 1, "kind": "static", "scene": field, "frames": poses}, open(path, "w"))
PY
  "$farfield" bench "$field" --path "$out/path_$count.json" -t brute,colorcube \
    --set colorcube.depth=$depth ${COLORCUBE_SETTINGS:-} --out "$out/bench_$count" --no-plot -q --samples 1 \
    --reference-every 5 | tail -n 3
  depth=$((depth + 1))
done

/usr/bin/python3 - "$out" <<'PY'
import json, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
out = sys.argv[1]
counts = [1, 4, 16, 64, 256]
rows = {"brute": ([], []), "colorcube": ([], [])}
sizes = []
for c in counts:
    b = json.load(open(f"{out}/bench_{c}/bench.json"))
    sizes.append(b["scene"]["triangles"])
    for t in b["techniques"]:
        rows[t["name"]][0].append(t["summary"]["median_ms"])
        rows[t["name"]][1].append(t["summary"]["mean_triangles"])
fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5), dpi=100)
for name, (ms, tris) in rows.items():
    a.loglog(sizes, ms, "o-", label=name)
    b.loglog(sizes, tris, "o-", label=name)
a.set_xlabel("scene triangles"); a.set_ylabel("median frame time (ms)"); a.grid(True, which="both", alpha=0.3); a.legend()
b.set_xlabel("scene triangles"); b.set_ylabel("triangles drawn per frame"); b.grid(True, which="both", alpha=0.3); b.legend()
fig.suptitle("paper 002 sub-linear experiment: fields of 1, 4, 16, 64, 256 trees")
fig.tight_layout()
fig.savefig(f"{out}/sublinear.png")
with open(f"{out}/sublinear.tsv", "w") as f:
    f.write("trees\ttriangles\tbrute_ms\tcolorcube_ms\tbrute_triangles\tcolorcube_triangles\n")
    for i, c in enumerate(counts):
        f.write(f"{c}\t{sizes[i]}\t{rows['brute'][0][i]:.2f}\t{rows['colorcube'][0][i]:.2f}\t{rows['brute'][1][i]:.0f}\t{rows['colorcube'][1][i]:.0f}\n")
print(open(f"{out}/sublinear.tsv").read())
PY
echo "plot: $out/sublinear.png"
