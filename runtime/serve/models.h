// The glTF models graphics components name (docs/viewer.md, "Models"): where `plant serve`
// finds them, and which it refuses. A model is looked up by its name, first under --models,
// then beside the plant, then among the standard library's models (stdlib/models), so a
// user's own model replaces the stdlib's of the same name.
#pragma once

#include "graph/graph.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace plant::view {

struct ModelDirs {
    std::string plant_dir, models_dir, stdlib_dir;  // stdlib_dir: models under stdlib_dir/models
};

// A model file is at most this large (a low-poly model is kilobytes, a detailed CAD export a
// few megabytes).
constexpr uint64_t kMaxModelBytes = 32u << 20;

// Whether a name names a model file (.glb or .gltf) rather than something else the viewer
// interprets ("" or a word: primitives).
bool model_name(std::string_view name);

// The file a model names, found and checked; empty `file` when there is none. `problem`
// says why a model name is not shown ("" when it is): not found (and where it was looked
// for), a name with '..', a file that is not glTF, one too large.
struct ModelLookup {
    std::string file, problem;
};
ModelLookup find_model(const ModelDirs& dirs, std::string_view name);

// A file a .gltf model refers to (its buffers, its textures), by its name relative to the
// models' folders: for the page's /models/ requests. Empty when none.
std::string find_model_resource(const ModelDirs& dirs, std::string_view name);

// Whether the file is a glTF model of acceptable size: empty, or the reason it is refused.
std::string check_model_file(const std::string& file);

// Every model name of the graph's graphics (and variants) that will not be shown, once each,
// with its problem: for the server's log and the page's notice.
struct ModelProblem {
    std::string model, problem;
};
std::vector<ModelProblem> model_problems(const graph::Graph& g, const ModelDirs& dirs);

}  // namespace plant::view
