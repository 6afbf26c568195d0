#include "serve/models.h"

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <system_error>

namespace plant::view {

namespace fs = std::filesystem;

namespace {

bool ends_with(std::string_view s, std::string_view ext) { return s.size() > ext.size() && s.ends_with(ext); }

// A relative name without '..', a leading '/', a backslash or a hidden segment: what may be
// looked up below a models folder.
bool plain_relative(std::string_view name) {
    if (name.empty() || name.front() == '/' || name.find('\\') != std::string_view::npos) return false;
    for (const auto& part : fs::path(std::string(name)))
        if (part == ".." || part.string().starts_with(".")) return false;
    return true;
}

std::vector<std::string> folders(const ModelDirs& dirs) {
    std::vector<std::string> out;
    if (!dirs.models_dir.empty()) out.push_back(dirs.models_dir);
    if (!dirs.plant_dir.empty()) out.push_back(dirs.plant_dir);
    if (!dirs.stdlib_dir.empty()) out.push_back((fs::path(dirs.stdlib_dir) / "models").string());
    return out;
}

std::string first_found(const ModelDirs& dirs, std::string_view name) {
    for (const std::string& dir : folders(dirs)) {
        std::error_code ec;
        const fs::path p = fs::path(dir) / std::string(name);
        if (fs::is_regular_file(p, ec)) return p.string();
    }
    return {};
}

}  // namespace

bool model_name(std::string_view name) { return ends_with(name, ".glb") || ends_with(name, ".gltf"); }

std::string check_model_file(const std::string& file) {
    std::error_code ec;
    const uint64_t size = fs::file_size(file, ec);
    if (ec) return fmt::format("'{}' cannot be read", file);
    if (size > kMaxModelBytes)
        return fmt::format("'{}' is {:.1f} MB, more than a model may be ({} MB)", file, double(size) / 1e6,
                           kMaxModelBytes >> 20);
    std::ifstream in(file, std::ios::binary);
    if (ends_with(file, ".glb")) {
        // The binary container's header: magic "glTF", version 2, the file's length.
        char head[12] = {};
        in.read(head, 12);
        uint32_t version = 0, length = 0;
        std::memcpy(&version, head + 4, 4);
        std::memcpy(&length, head + 8, 4);
        if (!in || std::memcmp(head, "glTF", 4) != 0) return fmt::format("'{}' is not a glTF binary (.glb) file", file);
        if (version != 2) return fmt::format("'{}' is glTF {}, not glTF 2", file, version);
        if (length != size) return fmt::format("'{}' is cut short or padded: its header says {} bytes, it has {}", file, length, size);
        return {};
    }
    std::string text(size_t(size), '\0');
    in.read(text.data(), std::streamsize(size));
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("asset") || !j["asset"].is_object())
        return fmt::format("'{}' is not a glTF (.gltf) file: not JSON with an \"asset\"", file);
    return {};
}

ModelLookup find_model(const ModelDirs& dirs, std::string_view name) {
    ModelLookup out;
    if (!model_name(name)) return out;
    if (!plain_relative(name)) {
        out.problem = fmt::format("'{}' is refused: a model is a name below the models' folders, without '..' or a "
                                  "leading '/'", name);
        return out;
    }
    const std::string file = first_found(dirs, name);
    if (file.empty()) {
        std::string where;
        for (const std::string& d : folders(dirs)) where += (where.empty() ? "" : ", ") + d;
        out.problem = fmt::format("'{}' was not found (looked in {})", name, where.empty() ? "no folder" : where);
        return out;
    }
    out.problem = check_model_file(file);
    if (out.problem.empty()) out.file = file;
    return out;
}

std::string find_model_resource(const ModelDirs& dirs, std::string_view name) {
    static constexpr std::string_view kKinds[] = {".bin", ".png", ".jpg", ".jpeg", ".webp", ".ktx2"};
    if (!plain_relative(name)) return {};
    for (std::string_view ext : kKinds)
        if (ends_with(name, ext)) {
            const std::string file = first_found(dirs, name);
            std::error_code ec;
            return !file.empty() && fs::file_size(file, ec) <= kMaxModelBytes && !ec ? file : std::string{};
        }
    return {};
}

std::vector<ModelProblem> model_problems(const graph::Graph& g, const ModelDirs& dirs) {
    std::set<std::string> names;
    for (const graph::Graphics& gr : g.graphics) {
        names.emplace(g.str(gr.model));
        for (int32_t v = 0; v < gr.variant_num; ++v) names.emplace(g.str(g.variants[gr.variant_adr + v].model));
    }
    std::vector<ModelProblem> out;
    for (const std::string& n : names)
        if (std::string problem = find_model(dirs, n).problem; !problem.empty()) out.push_back({n, std::move(problem)});
    return out;
}

}  // namespace plant::view
