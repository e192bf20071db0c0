// SPDX-License-Identifier: GPL-3.0-or-later
// mutool run scripts/pdf_mutool_region.js IN.pdf SCALE X Y W H OUT.png: MuPDF draws page 1 at SCALE (72 dpi = 1)
// into an RGBA pixmap covering output pixels [X, X+W) x [Y, Y+H).
var a = scriptArgs;
var page = new Document(a[0]).loadPage(0);
var s = parseFloat(a[1]), x = parseInt(a[2]), y = parseInt(a[3]);
var pix = new Pixmap(DeviceRGB, [x, y, x + parseInt(a[4]), y + parseInt(a[5])], true);
pix.clear();
var dev = new DrawDevice([s, 0, 0, s, 0, 0], pix);
page.run(dev, Identity);
dev.close();
pix.saveAsPNG(a[6]);
