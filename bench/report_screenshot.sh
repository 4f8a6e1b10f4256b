#!/usr/bin/env bash
# A PNG of a `visimp compare` report.html as a browser draws it, to check by eye that the
# plots' labels are legible and do not overlap (the SVGs are only ever looked at in a page).
#
# usage: bench/report_screenshot.sh REPORT.html OUT.png [WIDTH [HEIGHT]]
#   WIDTH × HEIGHT: the window in CSS pixels (default 1280 × 5000); the page is cut at HEIGHT.
# Installs Debian's `chromium` with apt-get when no Chromium is found (needs root).
set -euo pipefail
if (($# < 2 || $# > 4)); then
  echo "usage: $0 REPORT.html OUT.png [WIDTH [HEIGHT]]" >&2
  exit 2
fi
report=$1 out=$2 width=${3:-1280} height=${4:-5000}
[ -f "$report" ] || { echo "report_screenshot: no file $report" >&2; exit 1; }

find_chromium() {
  local name
  for name in chromium chromium-browser google-chrome; do
    command -v "$name" && return 0
  done
  return 1
}

if ! browser=$(find_chromium); then
  if [ "$(id -u)" -ne 0 ]; then
    echo "report_screenshot: no chromium found; run as root to install it (apt-get install chromium)" >&2
    exit 1
  fi
  echo "report_screenshot: installing chromium (apt-get)" >&2
  apt-get update -qq >&2
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >&2
  browser=$(find_chromium)
fi

# Chromium resolves file:// URLs and writes --screenshot relative to its own cwd: pass both absolute.
url="file://$(realpath "$report")"
out_abs="$(realpath -m "$out")"
# A throw-away profile, so the run neither reads nor leaves state in $HOME.
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
"$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir="$profile" \
  --window-size="$width,$height" --screenshot="$out_abs" "$url" 2>"$profile/log" \
  || { cat "$profile/log" >&2; exit 1; }
[ -s "$out_abs" ] || { echo "report_screenshot: chromium wrote no $out_abs" >&2; cat "$profile/log" >&2; exit 1; }
echo "$out_abs"
