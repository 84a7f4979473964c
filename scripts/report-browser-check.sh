#!/bin/bash
# The HTML report in a real browser (issue 24, item 6): headless Chromium opens
# REPORT/index.html, checks that every figure draws (each inline SVG has a non-empty box and
# something in it, each <img> and each picture inside an SVG (<image>, e.g. the report's
# inlined PNGs) decodes), that every link resolves (a relative file exists and
# reads, an in-page #anchor names an element; outside links are listed, not fetched: CI is
# offline), that the page says neither NaN nor undefined, and saves a screenshot.
#
#   scripts/report-browser-check.sh [REPORT_DIR (docs/report)] [SCREENSHOT (target/report-screenshot.png)]
#
# Installs Debian's chromium if it is missing (needs root). Exit 0 when every check passes.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
report=$(cd "${1:-$here/docs/report}" && pwd)
shot=${2:-$here/target/report-screenshot.png}
page="$report/index.html"
[ -f "$page" ] || { echo "report-browser-check: $page: no such file (build the report first)" >&2; exit 2; }

if ! command -v chromium >/dev/null; then
  echo "report-browser-check: installing chromium (apt-get)" >&2
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# A checker page that loads the report in a frame. --allow-file-access-from-files lets it
# read the frame's document and the linked files (file:// pages are otherwise cross-origin).
cat > "$work/check.html" <<EOF
<!doctype html><html><body><pre id="out">not finished</pre>
<iframe id="f" src="file://$page" style="width:1280px;height:900px"></iframe>
<script>
const out = document.getElementById('out');
function readable(url) {
  return new Promise(ok => {
    const x = new XMLHttpRequest();
    x.onload = () => ok(x.status === 0 || x.status === 200 ? x.responseText.length : -1);
    x.onerror = () => ok(-1);
    try { x.open('GET', url); x.send(); } catch (e) { ok(-1); }
  });
}
document.getElementById('f').onload = async () => {
  const lines = [], bad = [];
  const d = document.getElementById('f').contentDocument;
  const svgs = [...d.querySelectorAll('body svg')].filter(s => !s.parentElement.closest('svg'));
  svgs.forEach((s, k) => {
    const b = s.getBoundingClientRect();
    // A picture (image) counts: it is decoded on its own below.
    const marks = s.querySelectorAll('path, line, polyline, polygon, rect, circle, text, image').length;
    if (!(b.width > 10 && b.height > 10 && marks > 0))
      bad.push('figure ' + (k + 1) + ': ' + Math.round(b.width) + 'x' + Math.round(b.height) + ' px, ' + marks + ' marks');
  });
  const imgs = [...d.querySelectorAll('img')];
  imgs.forEach(i => { if (!(i.complete && i.naturalWidth > 0)) bad.push('image does not load: ' + i.getAttribute('src')); });
  // Pictures inside SVG figures: each href decoded as an image of its own.
  const pics = [...d.querySelectorAll('svg image')];
  for (const [k, p] of pics.entries()) {
    const src = p.getAttribute('href') || p.getAttribute('xlink:href') || '';
    const w = await new Promise(ok => {
      const i = new Image();
      i.onload = () => ok(i.naturalWidth);
      i.onerror = () => ok(0);
      i.src = new URL(src, d.baseURI).href;
    });
    if (!(w > 0)) bad.push('picture ' + (k + 1) + ' in an SVG does not decode: ' + src.slice(0, 40));
  }
  const links = [...d.querySelectorAll('a[href]')];
  let local = 0, anchors = 0, outside = [];
  for (const a of links) {
    const h = a.getAttribute('href');
    if (h.startsWith('#')) {
      anchors++;
      if (!d.getElementById(decodeURIComponent(h.slice(1)))) bad.push('anchor without target: ' + h);
    } else if (/^[a-z]+:/i.test(h) && !h.startsWith('file:')) {
      outside.push(h);
    } else {
      local++;
      if (await readable(a.href) <= 0) bad.push('link does not resolve: ' + h);
    }
  }
  // A value NaN, inf or undefined in a table cell or a figure's text (prose may name NaN).
  const text = d.body.innerText;
  const cells = [...d.querySelectorAll('td, th, svg text')];
  cells.forEach(c => {
    if (/(^|[^A-Za-z])(NaN|undefined|-?inf(inity)?)([^A-Za-z]|$)/i.test(c.textContent))
      bad.push('a value reads ' + JSON.stringify(c.textContent.trim().slice(0, 60)));
  });
  lines.push('figures ' + svgs.length + ' (inline SVG), images ' + imgs.length + ', pictures in SVG ' + pics.length);
  lines.push('links ' + links.length + ': ' + local + ' files, ' + anchors + ' anchors, ' + outside.length + ' outside (not fetched)');
  outside.forEach(h => lines.push('  outside ' + h));
  lines.push('text ' + text.length + ' characters, ' + cells.length + ' table cells and figure labels checked for NaN/inf');
  bad.forEach(b => lines.push('FAIL ' + b));
  lines.push(bad.length ? 'RESULT failed' : 'RESULT ok');
  out.textContent = lines.join('\n');
};
</script></body></html>
EOF

flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --allow-file-access-from-files)
dom=$(timeout 120 chromium "${flags[@]}" --virtual-time-budget=20000 --dump-dom "file://$work/check.html" 2>/dev/null || true)
result=$(printf '%s\n' "$dom" | sed -n '/<pre id="out">/,/<\/pre>/p' | sed -e 's/^.*<pre id="out">//' -e 's#</pre>##' \
  -e 's/&amp;/\&/g' -e 's/&lt;/</g' -e 's/&gt;/>/g')
echo "report-browser-check: $page"
printf '%s\n' "$result" | sed 's/^/  /'

# The screenshot: the top of the page at a laptop's width, tall enough for the first tables.
mkdir -p "$(dirname "$shot")"
timeout 120 chromium "${flags[@]}" --window-size=1280,2400 --virtual-time-budget=5000 \
  --screenshot="$work/shot.png" "file://$page" >/dev/null 2>&1 || true
if [ -s "$work/shot.png" ]; then
  mv "$work/shot.png" "$shot"
  echo "  screenshot $shot ($(stat -c %s "$shot") bytes)"
else
  echo "  FAIL no screenshot"
  exit 1
fi
printf '%s\n' "$result" | grep -q '^RESULT ok$'
