#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The PDF export measured on real images (issue 12's table): each image is vectorized
# (cached in OUT), exported with `sdvi export-pdf` (defaults), checked with qpdf, drawn by
# pdftoppm (poppler, over white), pdftocairo -transp (poppler's cairo backend, RGBA), MuPDF
# (mutool, RGBA) and pdf.js in headless Chromium (scripts/pdf_viewer.mjs, RGBA, its default
# canvas path and its WebGPU path; when scripts/npm has pdfjs-dist) at the image's size (x1)
# and at x4, and each drawing is compared
# with `sdvi render` at the same size (tests/pdf/pdf_fixture.cpp `compare`: PSNR over the
# pixels both draw opaque; alpha mismatches away from the domain's edge; the largest alpha
# painted outside the domain). x4 of images over 512 x 512 compares the central
# 2048 x 2048 output pixels. Sizes and times against cairo's ShadingType 7 mesh of the same
# surface come from bench_pdf, in the same run.
#   scripts/pdf_report.sh [BUILD_DIR] [OUT_DIR] [IMAGE...]
# Default images: the built-in sample, Lena, an icon with alpha, a 4K photo (../shared/data).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$root/out/pdf_report}
shift $(( $# >= 2 ? 2 : $# ))
data=${SDVI_DATA:-$root/../shared/data}
sdvi=$build/cli/sdvi fixture=$build/tests/pdf/sdvi_pdf_fixture bench=$build/bench/pdf/bench_pdf
for tool in "$sdvi" "$fixture" "$bench"; do [ -x "$tool" ] || { echo "missing $tool (build it)"; exit 1; }; done
for tool in qpdf pdftoppm pdftocairo mutool; do command -v $tool >/dev/null || { echo "missing $tool"; exit 1; }; done
have_pdfjs=0
[ -f "$root/scripts/npm/node_modules/pdfjs-dist/package.json" ] && command -v node >/dev/null && have_pdfjs=1
mkdir -p "$out"
images=("$@")
if [ ${#images[@]} -eq 0 ]; then
  [ -f "$out/sample.png" ] || "$sdvi" sample -o "$out/sample.png" >/dev/null
  images=("$out/sample.png" "$data/photos/lena_512.png" "$data/graphics/adwaita512_computer.png"
          "$data/large/fossa_3840x2160.jpg")
fi

# export IN.sdvi OUT.pdf: the CLI when this build has export-pdf, else the test fixture.
export_pdf() {
  if "$sdvi" export-pdf --help >/dev/null 2>&1; then "$sdvi" export-pdf "$1" -o "$2" --quiet
  else "$fixture" pdf "$1" "$2" >/dev/null; fi
}
json() { sed -n "s/.*\"$2\": *\([^,}]*\).*/\1/p" <<<"$1"; }

rows=()
sdvis=()
for img in "${images[@]}"; do
  name=$(basename "${img%.*}")
  sdvi_file="$out/$name.sdvi" pdf="$out/$name.pdf"
  if [ ! -f "$sdvi_file" ]; then
    echo "vectorizing $name ..." >&2
    nice "$sdvi" vectorize "$img" -o "$sdvi_file" --quiet >/dev/null
  fi
  sdvis+=("$sdvi_file")
  export -f export_pdf; export sdvi fixture
  times=$( { /usr/bin/time -f "%e %U" bash -c 'export_pdf "$0" "$1"' "$sdvi_file" "$pdf"; } 2>&1 | tail -1)
  read -r wall_s user_s <<<"$times"
  check_out=$(qpdf --check "$pdf" 2>&1 || true)
  check=$(grep -q "No syntax or stream encoding errors" <<<"$check_out" && echo ok || echo FAIL)
  info=$("$sdvi" info "$sdvi_file" --json | tr -d '\n ')
  w=$(json "$info" width); h=$(json "$info" height)
  for scale in 1 4; do
    ow=$((w * scale)) oh=$((h * scale)) base="$out/${name}_x$scale"
    if [ $scale -eq 1 ] || [ $((ow * oh)) -le $((2048 * 2048)) ]; then
      x=0 y=0 cw=$ow ch=$oh what="full"
      "$sdvi" render "$sdvi_file" -o "${base}_sdvi.png" --width $ow --height $oh >/dev/null
    else
      cw=$(( ow < 2048 ? ow : 2048 )) ch=$(( oh < 2048 ? oh : 2048 ))
      x=$(( (ow - cw) / 2 )) y=$(( (oh - ch) / 2 )) what="${cw}x$ch crop"
      "$sdvi" render "$sdvi_file" -o "${base}_sdvi.png" --scale $scale --region $x,$y,$cw,$ch >/dev/null
    fi
    dpi=$((72 * scale))
    pdftoppm -png -singlefile -r $dpi -x $x -y $y -W $cw -H $ch "$pdf" "${base}_pdftoppm"
    pdftocairo -png -singlefile -transp -r $dpi -x $x -y $y -W $cw -H $ch "$pdf" "${base}_pdftocairo"
    mutool run "$root/scripts/pdf_mutool_region.js" "$pdf" $scale $x $y $cw $ch "${base}_mutool.png" 2>/dev/null
    viewers=(pdftoppm pdftocairo mutool)
    for path_ in pdfjs pdfjs_webgpu; do
      flag=$([ $path_ = pdfjs ] || echo --webgpu)
      if [ $have_pdfjs = 1 ] && node "$root/scripts/pdf_viewer.mjs" $flag --scale $scale --region $x,$y,$cw,$ch \
                                  "$pdf" -o "${base}_$path_.png" >/dev/null; then
        viewers+=($path_)
      else
        viewers+=(none)
      fi
    done
    cells=""
    alpha=""
    for viewer in "${viewers[@]}"; do
      if [ $viewer = none ]; then cells+=" - |"; continue; fi
      r=$("$fixture" compare "${base}_$viewer.png" "${base}_sdvi.png")
      cells+=" $(printf '%.2f' "$(json "$r" psnr)") |"
      [ $viewer = pdftoppm ] || alpha+="$viewer $(json "$r" far_mismatch)/$(json "$r" outside_alpha | sed 's/0\.000000/0/') "
    done
    rows+=("| $name | ${w}x$h | x$scale ($what) |$cells $alpha| $(stat -c %s "$pdf") | $wall_s / $user_s | $check |")
  done
done

echo "PDF export vs \`sdvi render\` (PSNR in dB over pixels both draw opaque; alpha: pixels away from"
echo "the domain's edge whose alpha differs by > 0.5 / largest alpha painted outside the domain):"
echo
echo "| image | size | scale | pdftoppm | pdftocairo | mutool | pdf.js | pdf.js WebGPU | alpha far-mismatch/outside | PDF bytes | export s wall / CPU (CLI) | qpdf --check |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
echo
echo "Size and in-process write time against cairo's mesh pattern (ShadingType 7) of the same surface;"
echo "then the flat-shaded SVG export's text at the PDF's level, one coarser and one finer:"
echo
"$bench" "${sdvis[@]}" --svg

# `sdvi export-svg` (its default level: one below the PDF's, or the PDF's) as Chromium draws it, against the
# same `sdvi render` drawings as above (spec/SVG_EXPORT.md).
[ $have_pdfjs = 1 ] || exit 0
mkdir -p "$out/svg"
echo
echo "\`sdvi export-svg\` (flat-shaded, its default level), drawn by Chromium (crispEdges), vs \`sdvi render\`:"
echo
echo "| image | SVG | SVG bytes | SVG / PDF | Chromium x1 dB | Chromium x4 dB |"
echo "|---|---|---|---|---|---|"
for sdvi_file in "${sdvis[@]}"; do
  name=$(basename "${sdvi_file%.*}")
  svg=$out/svg/$name.svg
  "$sdvi" export-svg "$sdvi_file" -o "$svg" --quiet
  info=$("$sdvi" info "$sdvi_file" --json | tr -d '\n ')
  w=$(json "$info" width); h=$(json "$info" height)
  cells=""
  for scale in 1 4; do
    ow=$((w * scale)) oh=$((h * scale)) base="$out/${name}_x$scale"
    if [ $scale -eq 1 ] || [ $((ow * oh)) -le $((2048 * 2048)) ]; then x=0 y=0 cw=$ow ch=$oh
    else cw=$(( ow < 2048 ? ow : 2048 )) ch=$(( oh < 2048 ? oh : 2048 )) x=$(( (ow - cw) / 2 )) y=$(( (oh - ch) / 2 )); fi
    if node "$root/scripts/svg_viewer.mjs" --scale $scale --region $x,$y,$cw,$ch "$svg" -o "${base}_svg.png" >/dev/null; then
      cells+=" $(printf '%.2f' "$(json "$("$fixture" compare "${base}_svg.png" "${base}_sdvi.png")" psnr)") |"
    else cells+=" failed |"; fi
  done
  bytes=$(stat -c %s "$svg") pdf_bytes=$(stat -c %s "$out/$name.pdf")
  echo "| $name | $(basename "$svg") | $bytes | $(printf '%.1f' "$(echo "$bytes / $pdf_bytes" | bc -l)") |$cells"
done
