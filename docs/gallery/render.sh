#!/usr/bin/env bash
# Derives every example and renders its picture for docs/examples.md (needs Blender).
#   docs/gallery/render.sh [shapegram binary]
# Pictures go to docs/images/examples/<example>.jpg; rerun it when an example changes.
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/shapegram}
[ -x "$bin" ] || cargo build --release -q
out=docs/images/examples
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"

model() { # example -> the GLB its kind's command writes
  local file=$1 glb=$work/$(basename "$1").glb
  # The settings an example's own comment suggests, where its defaults show less of it.
  local settings=()
  case $(basename "$file") in rotating_tower.mul) settings=(--attr CurrentRot=15) ;; esac
  case $file in
    *.lsys) "$bin" lsystem "$file" -o "$glb" >/dev/null ;;
    *.cave) "$bin" cave "$file" -o "$glb" >/dev/null ;;
    *.grammar) "$bin" topo "$file" -q -o "$glb" ;;
    *) "$bin" derive "$file" -q -o "$glb" "${settings[@]}" ;;
  esac
  echo "$glb"
}

for file in examples/*.cga examples/*.mul examples/*.sgl examples/*.lsys examples/*.cave \
  examples/*.grammar examples/*.rpk; do
  # The word-only L-systems (algae, signal, parametric) draw nothing: their pictures are words.
  case $(basename "$file") in algae.lsys | signal.lsys | parametric.lsys) continue ;; esac
  name=$(basename "$file")
  blender -b --factory-startup -P docs/gallery/render.py -- "$(model "$file")" \
    "$PWD/$out/${name//./-}.jpg" >"$work/blender.log" 2>&1 \
    || { tail -20 "$work/blender.log" >&2; echo "error: rendering $file failed" >&2; exit 1; }
  echo "$out/${name//./-}.jpg"
done
