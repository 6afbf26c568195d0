#!/bin/sh
# Regenerates the viewer's screenshot (docs/images/viewer.png is a copy of it) and, beside
# it, OUT-arm.png, OUT-station.png and OUT-curve.png, close-ups of the arm, the filling
# station and a curve: runs the browser test on the bottling plant in its --docs mode, which
# runs the plant at 10x until a dozen bottles are out before it takes the picture.
#
#   viewer/screenshot.sh [OUT.png]      # default viewer/viewer.png
#
# Needs the ci build (scripts/build.sh ci) and `npm ci` in viewer/.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
out=${1:-$here/viewer.png}
plant=${PLANT:-$root/build/ci/app/plant}
exec node --experimental-websocket "$here/test/browser.mjs" "$plant" "$root/plants/bottling.plant" "$out" --docs
