#!/usr/bin/env bash
# Regenerates the standard library's glTF models (stdlib/models/*.glb) from the stdlib's own
# dimensions (viewer/models/make-models.mjs). Review the models in the viewer afterwards
# (viewer/screenshot.sh); the test `models_generated` checks the committed files are these.
#   bash scripts/make-models.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null   # node and the viewer's packages (@gltf-transform/core, three)
node viewer/models/make-models.mjs stdlib/models
