#include "analysis.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <istream>
#include <limits>
#include <numbers>
#include <sstream>

namespace plant::experiments {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// v rotated by the unit quaternion q (x y z w).
Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 u{q[0], q[1], q[2]};
    const Vec3 t = cross(u, v);
    const Vec3 t2{2 * t[0], 2 * t[1], 2 * t[2]};
    const Vec3 c = cross(u, t2);
    return {v[0] + q[3] * t2[0] + c[0], v[1] + q[3] * t2[1] + c[1], v[2] + q[3] * t2[2] + c[2]};
}
Quat conj(const Quat& q) { return {-q[0], -q[1], -q[2], q[3]}; }

// The bottle's axis (the body's z axis) in the world.
Vec3 axis(const Quat& q) { return rotate(q, {0, 0, 1}); }

bool inside(const graph::Field& f, const Vec3& p) {
    const Vec3 local = rotate(conj(f.pose.q), sub(p, f.pose.p));
    for (int i = 0; i < 3; ++i)
        if (std::abs(local[i]) > f.extent[i] / 2) return false;
    return true;
}

}  // namespace

int32_t body_named(const graph::Graph& g, const std::string& path) {
    for (size_t b = 0; b < g.bodies.size(); ++b)
        if (g.comp_path(g.bodies[graph::BodyId(b)].comp) == path) return int32_t(b);
    return -1;
}

int32_t field_at(const graph::Graph& g, const Vec3& p) {
    for (size_t i = 0; i < g.fields.size(); ++i)
        if (!g.fields[graph::FieldId(i)].body.valid() && g.fields[graph::FieldId(i)].enabled && inside(g.fields[graph::FieldId(i)], p)) return int32_t(i);
    return -1;
}

Rebound analyse_rebound(const std::vector<double>& t, const std::vector<double>& pitch) {
    Rebound r;
    for (size_t i = 0; i < pitch.size() && i < t.size(); ++i) {
        if (std::isnan(r.back_time)) {
            if (pitch[i] <= -1) continue;
            r.back_time = t[i];
            r.rebound = pitch[i];
        }
        r.rebound = std::max(r.rebound, pitch[i]);
    }
    return r;
}

bool find_bottle(const graph::Graph& g, std::string_view name, Bottle& out, std::string& error) {
    Bottle b;
    b.main = body_named(g, std::string(name) + ".main");
    b.bottom = body_named(g, std::string(name) + ".bottom");
    if (b.main < 0 || b.bottom < 0) {
        error = "the plant has no bottle '" + std::string(name) + "' (bodies " + std::string(name) + ".main and " +
                std::string(name) + ".bottom)";
        return false;
    }
    const graph::Body& m = g.bodies[graph::BodyId(b.main)];
    const graph::Body& f = g.bodies[graph::BodyId(b.bottom)];
    b.m_main = m.mass;
    b.m_bottom = f.mass;
    for (int32_t body : {b.main, b.bottom}) {
        const Vec3 p = g.bodies[graph::BodyId(body)].pose.p;  // the centre of mass is the body frame's origin
        double k = 0;
        for (size_t i = 0; i < g.fields.size(); ++i) {
            const graph::Field& fd = g.fields[graph::FieldId(i)];
            if (fd.body.valid() || !fd.enabled || !inside(fd, p)) continue;
            k += fd.gain;
            if (b.field < 0) {  // the main body's field, else the bottom body's
                b.field = int32_t(i);
                b.belt_speed = fd.speed;
                b.belt_dir = rotate(fd.pose.q, fd.dir);
            }
        }
        (body == b.main ? b.k_main : b.k_bottom) = k;
        b.gain_sum += k;
    }
    if (b.field < 0) {
        error = "the bottle '" + std::string(name) + "' does not start on a belt (in a force field)";
        return false;
    }
    const Vec3 c{(b.m_main * m.pose.p[0] + b.m_bottom * f.pose.p[0]) / b.mass(),
                 (b.m_main * m.pose.p[1] + b.m_bottom * f.pose.p[1]) / b.mass(),
                 (b.m_main * m.pose.p[2] + b.m_bottom * f.pose.p[2]) / b.mass()};
    b.gravity_along = dot(g.settings.gravity, b.belt_dir);
    b.z_main = m.pose.p[2] - c[2];
    b.z_bottom = f.pose.p[2] - c[2];
    // The tipping axis: horizontal, across the belt.
    const double h = std::hypot(b.belt_dir[0], b.belt_dir[1]);
    const Vec3 u{-b.belt_dir[1] / h, b.belt_dir[0] / h, 0};
    for (const graph::Body* body : {&m, &f}) {
        double own = 0;
        if (body->inertia_set) {  // principal moments about the body frame's axes
            for (int j = 0; j < 3; ++j) {
                Vec3 e{0, 0, 0};
                e[size_t(j)] = 1;
                const double c_j = dot(u, rotate(body->pose.q, e));
                own += body->inertia[size_t(j)] * c_j * c_j;
            }
        } else if (body->shape_num == 1 && g.shapes[body->shape_adr.first()].kind == graph::ShapeKind::Sphere) {
            const double r = g.shapes[body->shape_adr.first()].size[0];
            own = 0.4 * body->mass * r * r;  // Bullet's solid sphere
        } else {
            error = "the bottle's body '" + g.comp_path(body->comp) +
                    "' has neither an inertia nor a single sphere shape: its inertia is not known here";
            return false;
        }
        const Vec3 r = sub(body->pose.p, c);
        const double along_u = dot(r, u);
        b.inertia += own + body->mass * (dot(r, r) - along_u * along_u);
    }
    out = b;
    return true;
}

bool in_some_field(const graph::Graph& g, const Vec3& p) {
    for (const graph::Field& f : g.fields)
        if (!f.body.valid() && inside(f, p)) return true;
    return false;
}

bool frictionless(const graph::Graph& g) {
    return std::all_of(g.bodies.begin(), g.bodies.end(),
                       [](const graph::Body& b) { return b.friction == 0 && b.restitution == 0; });
}

double upright_speed(double t, double v0, double v_target, double gain_sum, double mass) {
    return v_target + (v0 - v_target) * std::exp(-gain_sum * t / mass);
}

double upright_time_to_fraction(double fraction, double gain_sum, double mass) {
    return -mass / gain_sum * std::log(1 - fraction);
}

double time_to_fraction(const std::vector<double>& t, const std::vector<double>& v, double target, double fraction) {
    const double level = fraction * target;
    const size_t n = std::min(t.size(), v.size());
    for (size_t i = 0; i < n; ++i) {
        if ((target >= 0 && v[i] < level) || (target < 0 && v[i] > level)) continue;
        if (i == 0) return t[0];
        const double s = (level - v[i - 1]) / (v[i] - v[i - 1]);
        return t[i - 1] + s * (t[i] - t[i - 1]);
    }
    return std::numeric_limits<double>::quiet_NaN();
}

double runtime_step_fraction(const Bottle& b, double dt) {
    const double M = b.mass(), k = b.k_main + b.k_bottom;
    if (k <= 0) return 0;
    const double kz = b.k_main * b.z_main + b.k_bottom * b.z_bottom;
    const double kzz = b.k_main * b.z_main * b.z_main + b.k_bottom * b.z_bottom * b.z_bottom;
    const double a = k * dt / M;
    const double inv_s = a / std::expm1(a);
    // (D/s + dt·A)·x = dt·A·(1, 0): Cramer's rule for the speed component.
    const double l11 = M * inv_s + dt * k, l12 = dt * kz, l22 = b.inertia * inv_s + dt * kzz;
    const double r1 = dt * k, r2 = dt * kz;
    return (r1 * l22 - l12 * r2) / (l11 * l22 - l12 * l12);
}

double runtime_upright_speed(double t, double v0, double v_target, const Bottle& b, double dt) {
    return v_target + (v0 - v_target) * std::pow(1 - runtime_step_fraction(b, dt), t / dt);
}

double lean_along(const Quat& q, const Vec3& dir) { return dot(axis(q), dir); }

std::vector<double> leaning_speed(const std::vector<double>& t, const std::vector<double>& lean, double v0,
                                  const Bottle& b) {
    const size_t n = std::min(t.size(), lean.size());
    std::vector<double> v(n);
    if (n == 0) return v;
    v[0] = v0;
    const double K = b.k_main + b.k_bottom, S = b.k_main * b.z_main + b.k_bottom * b.z_bottom, M = b.mass();
    for (size_t i = 1; i < n; ++i) {
        const double h = t[i] - t[i - 1];
        if (K <= 0) {  // no pull: only gravity and the lean's shift between the bodies
            v[i] = v[i - 1] + b.gravity_along * h;
            continue;
        }
        const double target = b.belt_speed + (M * b.gravity_along - S * (lean[i] - lean[i - 1]) / h) / K;
        v[i] = target + (v[i - 1] - target) * std::exp(-K * h / M);
    }
    return v;
}

Traction analyse_traction(const std::vector<double>& t, const std::vector<double>& v, const Bottle& b, double dt,
                          const std::vector<double>& lean) {
    Traction r;
    const size_t n = std::min(t.size(), v.size());
    if (n == 0) return r;
    if (lean.size() >= n) {
        const std::vector<double> law = leaning_speed(t, lean, v[0], b);
        for (size_t i = 0; i < n; ++i)
            if (std::abs(v[i] - law[i]) > std::abs(r.max_dev_lean)) r.max_dev_lean = v[i] - law[i], r.max_dev_lean_time = t[i];
    }
    const double v_target = b.belt_speed;
    r.t95 = time_to_fraction(t, v, v_target, 0.95);
    r.t95_analytic = upright_time_to_fraction(0.95, b.gain_sum, b.mass());
    r.t95_runtime = dt * std::log(0.05) / std::log(1 - runtime_step_fraction(b, dt));
    double top = v[0];
    r.overshoot = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < n; ++i) {
        const double dev = v[i] - upright_speed(t[i], v[0], v_target, b.gain_sum, b.mass());
        if (std::abs(dev) > std::abs(r.max_dev)) r.max_dev = dev, r.max_dev_time = t[i];
        const double dev_rt = v[i] - runtime_upright_speed(t[i], v[0], v_target, b, dt);
        if (std::abs(dev_rt) > std::abs(r.max_dev_runtime)) r.max_dev_runtime = dev_rt, r.max_dev_runtime_time = t[i];
        r.overshoot = std::max(r.overshoot, v[i] - v_target);
        top = std::max(top, v[i]);
        r.max_drop = std::max(r.max_drop, top - v[i]);
    }
    r.final_speed = v[n - 1];
    return r;
}

double tilt_deg(const Quat& q) {
    const Vec3 a = axis(q);
    return std::atan2(std::hypot(a[0], a[1]), a[2]) * kDeg;
}

double pitch_deg(const Quat& q, const Vec3& dir) {
    const Vec3 a = axis(q);
    const double h = std::hypot(dir[0], dir[1]);
    const double along = h > 0 ? (a[0] * dir[0] + a[1] * dir[1]) / h : 0;
    return std::atan2(along, a[2]) * kDeg;
}

Tipping analyse_tipping(const std::vector<double>& t, const std::vector<double>& pitch,
                        const std::vector<double>& tilt, const std::vector<double>& speed, double threshold_deg) {
    Tipping r;
    const size_t n = std::min({t.size(), pitch.size(), tilt.size(), speed.size()});
    if (n == 0) return r;
    for (size_t i = 0; i < n; ++i)
        if (tilt[i] > r.peak_tilt) r.peak_tilt = tilt[i], r.peak_time = t[i];
    // Swings: runs of |pitch| > threshold on one side.
    std::vector<Swing> swings;
    Swing cur;
    size_t first_end = n;
    for (size_t i = 0; i < n; ++i) {
        const int side = pitch[i] > threshold_deg ? 1 : pitch[i] < -threshold_deg ? -1 : 0;
        if (cur.found && side != cur.side) {
            swings.push_back(cur);
            if (swings.size() == 1) first_end = i;
            cur = Swing{};
        }
        if (side != 0) {
            if (!cur.found) cur = Swing{true, 0, t[i], side};
            if (std::abs(pitch[i]) > cur.peak) cur.peak = std::abs(pitch[i]), cur.time = t[i];
        }
    }
    if (cur.found) {
        swings.push_back(cur);
        if (swings.size() == 1) first_end = n;
    }
    if (!swings.empty()) r.first = swings[0];
    for (size_t s = 1; s < swings.size(); ++s)
        if (swings[s].peak > r.second.peak) r.second = swings[s];
    for (size_t i = swings.empty() ? 0 : first_end; i < n; ++i) r.later_max = std::max(r.later_max, tilt[i]);
    r.final_tilt = tilt[n - 1];
    r.final_speed = speed[n - 1];
    return r;
}

Stats stats(const std::vector<double>& x) {
    Stats s;
    s.n = x.size();
    if (x.empty()) return s;
    s.min = *std::min_element(x.begin(), x.end());
    s.max = *std::max_element(x.begin(), x.end());
    double sum = 0;
    for (double v : x) sum += v;
    s.mean = sum / double(x.size());
    double sq = 0;
    for (double v : x) sq += (v - s.mean) * (v - s.mean);
    s.variance = sq / double(x.size());
    return s;
}

int laps(const std::vector<double>& x, const std::vector<double>& y, const Vec3& dir, double half_width) {
    const size_t n = std::min(x.size(), y.size());
    if (n < 2) return 0;
    const double len = std::hypot(dir[0], dir[1]);
    const double dx = dir[0] / len, dy = dir[1] / len;
    // A crossing counts once the path has been away from the gate (so jitter at the
    // start, or on the gate, is not a lap).
    const double away = std::max(0.5, 4 * half_width);
    int count = 0;
    bool armed = false;
    double prev_s = 0;
    for (size_t i = 0; i < n; ++i) {
        const double rx = x[i] - x[0], ry = y[i] - y[0];
        const double s = rx * dx + ry * dy;
        const double lateral = std::abs(-rx * dy + ry * dx);
        if (std::hypot(rx, ry) > away) armed = true;
        if (i > 0 && armed && prev_s < 0 && s >= 0 && lateral <= half_width) {
            ++count;
            armed = false;
        }
        prev_s = s;
    }
    return count;
}

std::vector<double> track_gap(const std::vector<double>& ax, const std::vector<double>& ay,
                              const std::vector<double>& bx, const std::vector<double>& by, double reach,
                              double max_gap) {
    const size_t n = std::min({ax.size(), ay.size(), bx.size(), by.size()});
    std::vector<double> gap(n, std::nan(""));
    if (n < 2) return gap;
    std::vector<double> s(n, 0);  // b's path length
    for (size_t j = 1; j < n; ++j) s[j] = s[j - 1] + std::hypot(bx[j] - bx[j - 1], by[j] - by[j - 1]);
    constexpr double kHeadingBase = 0.01;  // m of a's path that give its heading
    size_t back = 0, from = 0;
    for (size_t i = 0; i < n; ++i) {
        // a's heading: from the latest sample at least kHeadingBase behind it, else ahead.
        while (back + 1 < i && std::hypot(ax[i] - ax[back + 1], ay[i] - ay[back + 1]) >= kHeadingBase) ++back;
        double hx = ax[i] - ax[back], hy = ay[i] - ay[back];
        if (std::hypot(hx, hy) < kHeadingBase) {
            size_t k = i;
            while (k + 1 < n && std::hypot(ax[k] - ax[i], ay[k] - ay[i]) < kHeadingBase) ++k;
            hx = ax[k] - ax[i], hy = ay[k] - ay[i];
        }
        const double hl = std::hypot(hx, hy);
        if (hl == 0) continue;
        hx /= hl, hy /= hl;
        auto ahead = [&](size_t j) { return (bx[j] - ax[i]) * hx + (by[j] - ay[i]) * hy; };
        for (size_t j = std::max(from, i); j + 1 < n && s[j] - s[i] <= max_gap; ++j) {
            const double p0 = ahead(j), p1 = ahead(j + 1);
            if (p0 < 0 && p1 >= 0 && std::hypot(bx[j + 1] - ax[i], by[j + 1] - ay[i]) <= reach) {
                const double f = -p0 / (p1 - p0);
                gap[i] = s[j] + f * (s[j + 1] - s[j]) - s[i];
                from = j;  // a moves on, so b's crossing for the next sample is not earlier
                break;
            }
        }
    }
    return gap;
}

std::vector<Straight> straights(const graph::Graph& g) {
    std::vector<Straight> out;
    for (const graph::Field& f : g.fields) {
        if (f.body.valid() || !f.enabled || f.dir[0] < 0.999 || f.extent[0] < 2 * f.extent[1]) continue;
        const std::string path = g.comp_path(f.comp);
        Straight s;
        s.name = path.substr(0, path.find('.'));
        s.centre = f.pose.p;
        s.dir = rotate(f.pose.q, f.dir);
        s.length = f.extent[0];
        s.width = f.extent[1];
        s.speed = f.speed;
        out.push_back(s);
    }
    return out;
}

std::vector<Crossing> crossings(const std::vector<double>& t, const std::vector<double>& x, const std::vector<double>& y,
                                const Vec3& point, const Vec3& dir, double half_width) {
    std::vector<Crossing> out;
    const size_t n = std::min({t.size(), x.size(), y.size()});
    auto along = [&](size_t i) { return (x[i] - point[0]) * dir[0] + (y[i] - point[1]) * dir[1]; };
    auto across = [&](size_t i) { return dir[0] * (y[i] - point[1]) - dir[1] * (x[i] - point[0]); };
    for (size_t i = 1; i < n; ++i) {
        const double s0 = along(i - 1), s1 = along(i);
        if (!(s0 < 0 && s1 >= 0)) continue;
        const double f = -s0 / (s1 - s0);
        const double lateral = across(i - 1) + f * (across(i) - across(i - 1));
        if (std::abs(lateral) <= half_width) out.push_back({t[i - 1] + f * (t[i] - t[i - 1]), lateral});
    }
    return out;
}

const std::vector<double>* Table::col(std::string_view name) const {
    for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return &cols[i];
    return nullptr;
}

bool read_csv(std::istream& in, Table& out, std::string& error) {
    Table t;
    std::string line;
    if (!std::getline(in, line)) {
        error = "empty trace";
        return false;
    }
    // A trace's text columns (docs/runtime.md, "Trace columns"): the objects lost and the slots
    // forced at each row, often empty; their cells hold no comma. Left out of the table.
    std::vector<int32_t> column;  // per cell of a row: its column in the table, -1 left out
    {
        std::istringstream h(line);
        for (std::string name; std::getline(h, name, ',');) {
            const bool text = name == "lost" || name == "forced";
            column.push_back(text ? -1 : int32_t(t.names.size()));
            if (!text) t.names.push_back(name);
        }
    }
    t.cols.resize(t.names.size());
    for (size_t row = 2; std::getline(in, line); ++row) {
        if (line.empty()) continue;
        std::istringstream r(line);
        size_t c = 0;
        for (std::string cell; std::getline(r, cell, ','); ++c) {
            if (c < column.size() && column[c] < 0) continue;
            char* end = nullptr;
            const double v = std::strtod(cell.c_str(), &end);
            if (c >= column.size() || cell.empty() || *end != '\0') {
                error = "line " + std::to_string(row) + ": '" + cell + "' is not a number of a known column";
                return false;
            }
            t.cols[size_t(column[c])].push_back(v);
        }
        // getline yields no cell for an empty last one (a text column at the end).
        if (c + 1 == column.size() && column.back() < 0 && !line.empty() && line.back() == ',') ++c;
        if (c != column.size()) {
            error = "line " + std::to_string(row) + ": " + std::to_string(c) + " values for " +
                    std::to_string(column.size()) + " columns";
            return false;
        }
    }
    out = std::move(t);
    return true;
}

bool read_csv_file(const std::string& path, Table& out, std::string& error) {
    std::ifstream in(path);
    if (!in) {
        error = path + ": cannot open";
        return false;
    }
    if (!read_csv(in, out, error)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

}  // namespace plant::experiments
