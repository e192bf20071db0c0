#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Hostile SVG inputs through `sdvi import-svg` (spec/SVG.md, "Safety"; issue 10, must show
# 4, and what else was found): each file is generated here, the command must exit 1 with its [error name] and write
# no file; the table gives CPU seconds (user + sys, which a loaded machine does not
# inflate), wall seconds and peak RSS. `sdvi -V` alone is the first row: what starting the
# process costs.
#   usage: bench/svg/hostile.sh [SDVI (default build/cli/sdvi)]
set -euo pipefail
SDVI=$(realpath "${1:-build/cli/sdvi}")
DIR=$(mktemp -d)
trap 'rm -rf "$DIR"' EXIT
python3 - "$DIR" <<'EOF'
import sys
d = sys.argv[1]
H = ('<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
     'width="64" height="64">')
def svg(body): return H + body + '</svg>'
laughs = '<?xml version="1.0"?>\n<!DOCTYPE svg [\n<!ENTITY lol "lol">\n'
for i in range(1, 10):
    ref = '&lol%s;' % ('' if i == 1 else str(i - 1))
    laughs += '<!ENTITY lol%d "%s">\n' % (i, ref * 10)
open(d + '/secret.txt', 'w').write('SECRET')
cases = {
    'billion_laughs': laughs + ']>\n' + svg('<text y="20">&lol9;</text>'),
    'external_entity': '<?xml version="1.0"?>\n<!DOCTYPE svg [<!ENTITY s SYSTEM "file://' + d +
                       '/secret.txt">]>\n' + svg('<text y="20">&s;</text>'),
    'xinclude': '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xi="http://www.w3.org/2001/XInclude" '
                'width="64" height="64"><xi:include href="/etc/passwd" parse="text"/></svg>',
    'elements_1e6': svg('<g/>' * 1000000),
    'nested_1e4': svg('<g>' * 10000 + '<rect width="1" height="1"/>' + '</g>' * 10000),
    'path_1e7': svg('<path d="M0 0' + 'h1v1' * 5000000 + '"/>'),
    'width_1e9': '<svg xmlns="http://www.w3.org/2000/svg" width="1000000000" height="10">'
                 '<rect width="5" height="5"/></svg>',
    'use_self': svg('<g id="a"><use xlink:href="#a"/></g>'),
    'malformed': svg('<g><rect width="1" height="1"></g>'),
    'bad_path': svg('<path d="M 10 10 L 20"/>'),
    'far_dashes': svg('<path d="M10 10 L1.6e49 30 L30 60z" fill="red" stroke="black" '
                      'stroke-width="3" stroke-dasharray="2 2"/>'),
    'hidden_dashes': svg('<style>path{stroke-dasharray:0.01 !important}</style>'
                         '<path d="M10 10 L4e6 30" stroke="black" fill="none"/>'),
    'css_escape': svg('<path d="M0 0h9" style="stroke-d\\61sharray:1"/>'),
    'nested_svg': svg('<image width="9" height="9" href="data:image/svg+xml;base64,PHN2Zy8+"/>'),
}
# A PNG declaring 20000 x 20000 grey pixels, all zero: 389 KB, 1.6 GB once decoded.
import base64, struct, zlib
def chunk(kind, data):
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data))
z = zlib.compressobj(9)
rows = b''.join(z.compress(b'\0' * 20001) for _ in range(20000)) + z.flush()
png = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 20000, 20000, 8, 0, 0, 0, 0)) +
       chunk(b'IDAT', rows) + chunk(b'IEND', b''))
cases['image_bomb'] = svg('<image width="64" height="64" href="data:image/png;base64,' +
                          base64.b64encode(png).decode() + '"/>')
for name, text in cases.items():
    open(d + '/' + name + '.svg', 'w').write(text)
EOF
printf '%-16s %5s %8s %8s %7s  %-26s %s\n' case exit "cpu s" "wall s" "RSS MB" error written
row() {  # name, then the command
  local name=$1
  shift
  local rc=0
  /usr/bin/time -f '%e %U %S %M' -o "$DIR/time" "$@" >"$DIR/out" 2>&1 || rc=$?
  read -r wall user sys kb < <(tail -1 "$DIR/time")  # after "Command exited with ..."
  local error written=no
  error=$(grep -o '\[[a-z_]*\]' "$DIR/out" | head -1 || true)
  [ -e "$DIR/$name.sdvi" ] && written=yes
  grep -q SECRET "$DIR/out" && error="$error SECRET LEAKED"
  printf '%-16s %5d %8.2f %8.2f %7d  %-26s %s\n' "$name" "$rc" "$(echo "$user + $sys" | bc)" "$wall" \
    $((kb / 1024)) "$error" "$written"
}
row "sdvi -V" "$SDVI" -V
for f in billion_laughs external_entity xinclude elements_1e6 nested_1e4 path_1e7 width_1e9 use_self \
         malformed bad_path far_dashes hidden_dashes css_escape nested_svg image_bomb; do
  row "$f" "$SDVI" import-svg "$DIR/$f.svg" -o "$DIR/$f.sdvi"
done
