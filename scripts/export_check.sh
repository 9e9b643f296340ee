#!/usr/bin/env bash
# Exports model files (imported first) or .ffscene files as glb, validates each with the Khronos
# glTF validator, imports it again and compares counts: one line a model.
#   scripts/export_check.sh OUT_DIR FILE...
# Needs build/farfield (or FARFIELD) and web/'s npm packages (make deps).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
farfield="${FARFIELD:-$here/build/farfield}"
out="${1:?usage: scripts/export_check.sh OUT_DIR FILE...}"
shift
mkdir -p "$out"
printf '%-28s %10s %8s %10s %9s %8s %s\n' model triangles objects glb_MB export_s errors \
  "again: triangles, objects"
status=0
for file in "$@"; do
  name="$(basename "$file")"
  name="${name%.*}"
  scene="$out/$name.ffscene"
  case "$file" in
    *.ffscene) cp "$file" "$scene" ;;
    *) if ! "$farfield" import -q "$file" --out "$scene" > /dev/null; then
         printf '%-28s import refused (above)\n' "$name"
         continue
       fi ;;
  esac
  start=$(date +%s.%N)
  line=$("$farfield" export "$scene" --out "$out/$name.glb")
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  triangles=$(echo "$line" | sed -E 's/.* ([0-9]+) triangles?.*/\1/')
  objects=$(echo "$line" | sed -E 's/.*: ([0-9]+) objects?.*/\1/')
  errors=$(node "$here/web/validate_glb.mjs" "$out/$name.glb" | head -1 | sed -E 's/.*: ([0-9]+) errors.*/\1/')
  again=$("$farfield" import -q "$out/$name.glb" --out "$out/$name.again.ffscene")
  again_triangles=$(echo "$again" | sed -E 's/.*: ([0-9]+) triangles?.*/\1/')
  again_objects=$(echo "$again" | sed -E 's/.*, ([0-9]+) objects?.*/\1/')
  bytes=$(stat -c %s "$out/$name.glb")
  printf '%-28s %10s %8s %10.2f %9.2f %8s %s, %s\n' "$name" "$triangles" "$objects" \
    "$(echo "$bytes / 1000000" | bc -l)" "$seconds" "$errors" "$again_triangles" "$again_objects"
  if [ "$errors" != 0 ] || [ "$again_triangles" != "$triangles" ] || [ "$again_objects" != "$objects" ]; then
    status=1
  fi
done
exit $status
