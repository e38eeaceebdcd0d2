#!/usr/bin/env bash
# Six-field impostors (Baboud & Décoret §4; issue 22) measured against the meshes
# themselves, into docs/report/impostors.md: the Stanford bunny of data/ (npm bunny
# 1.0.1, public domain) and the procedural tower (`hfcast impostor export tower`).
#   1. render_osmesa impostor-report: the impostor drawn through the generated GLSL
#      (llvmpipe, software) against the mesh rasterized by OpenGL from the same three
#      cameras, per frustum, side (32² to 512²) and combination: silhouette pixels
#      wrong, depth error, frame times and fragments of the clipped and unclipped
#      proxies, capture times.
#   2. hfcast impostor colours: colour texels against the mesh's colour, depth side
#      against colour side (the textures' resolution is independent of the fields').
#   3. Two CPU renders (hfcast impostor render) beside the report.
# About 3 minutes on 2 cores.
#   bash scripts/impostors.sh
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=docs/report/impostors.md
IMG=docs/report/impostors
export MESA_SHADER_CACHE_DISABLE=true
cargo build -q --release -p hfcast-tools -p hfcast-capi
make -s -C c_tests HFCAST_LIB_DIR=../target/release OUT=../target/c_tests ../target/c_tests/render_osmesa ../target/c_tests/tower.obj
BUNNY=data/mesh_stanford_bunny.obj
TOWER=target/c_tests/tower.obj
gl=$(./target/c_tests/render_osmesa impostor-report 320 256 "$BUNNY" "$TOWER")
colours=$(./target/release/hfcast impostor colours "$BUNNY" --depth-sides 32,64,128,256 --colour-sides 32,128,512)
mkdir -p "$IMG"
for mesh in bunny tower; do
  src=$BUNNY; [ "$mesh" = tower ] && src=tower
  for f in orthographic reverse-perspective; do
    ./target/release/hfcast impostor capture "$src" --side 64 --colour-side 256 --frustum "$f" --out "target/impostors/$mesh-$f" > /dev/null
    ./target/release/hfcast impostor render "target/impostors/$mesh-$f" --width 256 --height 256 --out "$IMG/$mesh-$f-64.png" > /dev/null
  done
done
{
  echo "# Six-field impostors against the meshes"
  echo
  echo "Made by \`bash scripts/impostors.sh\` (issue 22). Baboud & Décoret (2006) §4 replace an object by"
  echo "six reverse-perspective height fields on the faces of its bounding cube; hfcast captures them from"
  echo "a triangle mesh by exact rasterization in grid space (\`hfcast::impostor\`, \`hf_impostor_capture\`,"
  echo "\`hfcast impostor capture\`) and traces them with the exact traversal on every field, on the CPU and"
  echo "in the generated GLSL and WGSL. Meshes: the Stanford bunny (\`data/mesh_stanford_bunny.obj\`, from"
  echo "the npm package \`bunny\` 1.0.1, public domain; the scan is the Stanford 3D Scanning Repository's,"
  echo "acknowledged here; 1,839 vertices, 3,674 triangles) and the procedural tower"
  echo "(\`hfcast impostor export tower\`: a tower of revolution with a ring, tilted off the axes; 2,176"
  echo "triangles)."
  echo
  echo "Two ways to make the object of six fields (\`Combine\`):"
  echo
  echo "- **intersection** (hfcast's default): the first point of the ray inside all six solids, a visual"
  echo "  hull of height fields; each field carves what it sees. About three field traces per pixel."
  echo "- **facing field**: only the field the ray looks at most directly, as the paper draws each face"
  echo "  with its own field. One trace per pixel."
  echo
  echo "The ground truth is the mesh rasterized by OpenGL (OSMesa) from the same cameras; a pixel's"
  echo "silhouette is wrong when one covers it and the other does not; the depth error is the mean"
  echo "difference of the forward distance of the pixels both cover, in half sides of the cube. The"
  echo "*clipped* proxy is the cube (each face's frustum clipped by the bounding box, §4.1), the"
  echo "*unclipped* one the six frusta; both give the same image (checked in \`render_osmesa impostor\`),"
  echo "the fragments are those the impostor's shader ran (an atomic counter)."
  echo
  echo "## What the tables show"
  echo
  echo "- **One field per ray (the paper's renderer): the reverse perspective wins.** At every side and on"
  echo "  both meshes it has fewer wrong silhouette pixels and a smaller depth error than the orthographic"
  echo "  fields (bunny 64²: 13.7 % against 31.3 % of the silhouette, 0.014 against 0.030 half sides): its"
  echo "  projector lines cross the sides the ray sees, where an orthographic field holds only their"
  echo "  extrusion. This is the paper's claim, and it holds."
  echo "- **The intersection of the six fields is hfcast's default, and there the orthographic fields win.**"
  echo "  It has 2.5 to 135 times fewer wrong silhouette pixels than one field per ray (bunny 64²"
  echo "  orthographic: 1.3 % of the silhouette wrong against 31 %). In it every field's sampling error cuts"
  echo "  into the object, and a reverse-perspective field sees more of the surface at grazing angles, where"
  echo "  the interpolation between samples cuts corners; so the orthographic fields are about twice as"
  echo "  accurate at equal side (bunny 64²: 1.3 % against 3.1 %). \`core/tests/impostor.rs\` measures the"
  echo "  same on the CPU (and that a stronger perspective, a smaller apex, is worse in the intersection and"
  echo "  better for one field per ray)."
  echo "- **Clipping the frusta by the box (§4.1) pays**: the same image from about 5.5 times fewer fragments"
  echo "  and 5 to 6 times less time. The clipped proxy's fragments do not depend on the side."
  echo "- **Frame time grows with the side** (the exact traversal walks more cells): about 30 ms at 32² to"
  echo "  150–200 ms at 512² for the intersection on llvmpipe, less than half that for one field per ray. The"
  echo "  meshes themselves rasterize in 1–5 ms: these are small meshes; an impostor pays where the mesh is"
  echo "  large or far away, and no GPU was lent to measure one."
  echo "- **Colour at its own side**: the colour error falls with the colour textures' side at any field"
  echo "  side (fields of 32²: 19 % of pixels off at colour 32², 10 % at 512²), so colour can be sharper than"
  echo "  the geometry, as §4.3 proposes."
  echo
  echo "## Silhouette, depth, frame time and fragments (OSMesa)"
  echo
  echo "Made by \`render_osmesa impostor-report 320 256 mesh_stanford_bunny.obj tower.obj\` (c_tests/render_osmesa.c)."
  echo
  echo "$gl"
  echo
  echo "## Colour at its own resolution"
  echo
  echo "$colours"
  echo
  echo "## Pictures (CPU, \`hfcast impostor render\`, fields of 64², textures of 256², intersection)"
  echo
  echo "| | orthographic | reverse perspective |"
  echo "|---|---|---|"
  echo "| bunny | ![](impostors/bunny-orthographic-64.png) | ![](impostors/bunny-reverse-perspective-64.png) |"
  echo "| tower | ![](impostors/tower-orthographic-64.png) | ![](impostors/tower-reverse-perspective-64.png) |"
} > "$OUT"
echo "impostors: wrote $OUT"
