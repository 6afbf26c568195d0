#include "serve/protocol.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace plant::view {

using json = nlohmann::json;

namespace {

// An input's path (one dotted path) and its optional "value" (as an events file writes it).
bool input_fields(const json& j, const std::string& path, std::string& value, std::string& error) {
    auto it = j.find("value");
    if (it != j.end() && !it->is_null()) {
        if (it->is_string()) value = it->get<std::string>();
        else if (it->is_boolean()) value = it->get<bool>() ? "true" : "false";
        else if (it->is_number()) value = it->dump();
        else {
            error = "\"value\" must be a string, a number or a boolean";
            return false;
        }
    }
    if (path.empty() || path.find_first_of(" \t\r\n") != std::string::npos) {
        error = "\"path\" must be a dotted path without spaces";
        return false;
    }
    if (value.find_first_of("\r\n") != std::string::npos) {
        error = "\"value\" must be one line";
        return false;
    }
    return true;
}

bool string_field(const json& j, const char* key, std::string& out, std::string& error, bool required = true) {
    auto it = j.find(key);
    if (it == j.end()) {
        if (!required) return true;
        error = std::string("missing \"") + key + "\"";
        return false;
    }
    if (!it->is_string()) {
        error = std::string("\"") + key + "\" must be a string";
        return false;
    }
    out = it->get<std::string>();
    return true;
}

bool number_field(const json& j, const char* key, double& out, std::string& error) {
    auto it = j.find(key);
    if (it == j.end() || !it->is_number()) {
        error = std::string("\"") + key + "\" must be a number";
        return false;
    }
    out = it->get<double>();
    if (!std::isfinite(out)) {
        error = std::string("\"") + key + "\" must be finite";
        return false;
    }
    return true;
}

}  // namespace

bool decode_client_message(std::string_view text, ClientMessage& m, std::string& error) {
    m = ClientMessage{};
    if (text.size() > kMaxClientMessage) {
        error = "message too long";
        return false;
    }
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded()) {
        error = "malformed JSON";
        return false;
    }
    if (!j.is_object()) {
        error = "a message is a JSON object";
        return false;
    }
    std::string type;
    if (!string_field(j, "type", type, error)) return false;
    if (type == "hello") {
        m.kind = ClientMessage::Kind::Hello;
        if (j.contains("fps")) {
            double fps = 0;
            if (!number_field(j, "fps", fps, error)) return false;
            if (fps < 1 || fps > 60) {
                error = "\"fps\" must lie between 1 and 60";
                return false;
            }
            m.fps = int(fps);
        }
        return true;
    }
    if (type == "control") {
        m.kind = ClientMessage::Kind::Control;
        if (!string_field(j, "action", m.action, error)) return false;
        if (m.action == "speed") {
            if (!number_field(j, "speed", m.speed, error)) return false;
            if (m.speed != 0 && (m.speed < 0.01 || m.speed > 1000)) {
                error = "\"speed\" is 0 (as fast as possible) or 0.01 to 1000 times real time";
                return false;
            }
            return true;
        }
        if (m.action == "pause" || m.action == "run" || m.action == "step" || m.action == "restart") return true;
        error = "unknown control action '" + m.action + "' (pause, run, step, restart, speed)";
        return false;
    }
    if (type == "force") {  // {"type":"force","path":P,"mode":"stuck"|"open"|"invert"|"release","value":V}
        m.kind = ClientMessage::Kind::Event;
        std::string mode, value;
        if (!string_field(j, "path", m.path, error) || !string_field(j, "mode", mode, error)) return false;
        if (mode != "stuck" && mode != "open" && mode != "invert" && mode != "release") {
            error = "\"mode\" is stuck, open, invert or release";
            return false;
        }
        if (!input_fields(j, m.path, value, error)) return false;
        // The text an events file holds ("force P open"): parsed by the server like every input.
        m.value = mode == "release" ? std::string() : mode + (value.empty() ? "" : " " + value);
        m.path = (mode == "release" ? "release " : "force ") + m.path;
        return true;
    }
    if (type == "hand") {  // {"type":"hand","action":"grab"|"move"|"drop"|"remove","path":P,"point":[x,y,z]}
        m.kind = ClientMessage::Kind::Event;
        std::string action, path;
        if (!string_field(j, "action", action, error) || !string_field(j, "path", path, error)) return false;
        if (action != "grab" && action != "move" && action != "drop" && action != "remove") {
            error = "\"action\" is grab, move, drop or remove";
            return false;
        }
        std::string none;
        if (!input_fields(json::object(), path, none, error)) return false;
        m.path = action + " " + path;  // the events-file text, parsed by the server like every input
        if (action == "grab" || action == "move") {
            auto it = j.find("point");
            if (it == j.end() || !it->is_array() || it->size() != 3) {
                error = "\"point\" must be [x, y, z]";
                return false;
            }
            std::string xyz;
            for (const json& v : *it) {
                if (!v.is_number() || !std::isfinite(v.get<double>())) {
                    error = "\"point\" must be three finite numbers";
                    return false;
                }
                xyz += (xyz.empty() ? "" : ",") + v.dump();
            }
            m.value = (action == "grab" ? "at " : "to ") + xyz;
        }
        return true;
    }
    if (type == "event") {
        m.kind = ClientMessage::Kind::Event;
        return string_field(j, "path", m.path, error) && input_fields(j, m.path, m.value, error);
    }
    if (type == "inspect") {
        m.kind = ClientMessage::Kind::Inspect;
        auto it = j.find("path");
        if (it == j.end() || it->is_null()) {
            m.stop_inspect = true;
            return true;
        }
        return string_field(j, "path", m.path, error);
    }
    if (type == "drill" && j.contains("cancel")) {  // {"type":"drill","cancel":2}: a waiting drill dropped
        m.kind = ClientMessage::Kind::DrillCancel;
        const json& n = j.at("cancel");
        if (!n.is_number_integer() || n.get<int64_t>() < 1 || n.get<int64_t>() > 1000000) {
            error = "\"cancel\" is a drill's number (1, 2, ... as the status's drills list them)";
            return false;
        }
        m.drill = int(n.get<int64_t>());
        return true;
    }
    if (type == "drill") {  // {"type":"drill","line":"when PATH >= N force PATH open"} (the instructor's)
        m.kind = ClientMessage::Kind::Drill;
        return string_field(j, "line", m.path, error);
    }
    if (type == "seek") {
        m.kind = ClientMessage::Kind::Seek;
        if (!number_field(j, "time", m.time, error)) return false;
        if (m.time < 0) {
            error = "\"time\" must not be negative";
            return false;
        }
        return true;
    }
    error = "unknown message type '" + type + "'";
    return false;
}

}  // namespace plant::view
