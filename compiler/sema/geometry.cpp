// Conveyor ends that nearly meet (W0601): every field that moves things has an outlet, the
// middle of the bottom edge of its box's face that the field pulls towards. 5 mm past that
// point the next conveyor's box must begin, with its bottom at the same height, and a lane
// that runs on in about the same direction must not be shifted aside. An outlet that meets
// nothing is the end of a line (a store, an exit); one that misses a conveyor starting within
// 20 cm ahead of it is a mistake: a bottle there stops or falls, and the plant compiles clean
// (docs/diagnostics.md, W0601, says the rule).
#include "sema/elaborator.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <fmt/format.h>
#include <set>
#include <tuple>
#include <unordered_map>

namespace plant::sema {

namespace {

constexpr double kGap = 5e-3;       // a gap or step up to this is a meeting
constexpr double kAside = 5e-3;     // a lane shifted aside by up to this (beyond any difference of widths)
constexpr double kCapture = 0.20;   // a conveyor starting within this of an outlet was meant to meet it
constexpr double kParallel = 0.866; // cos 30°: lanes this close in direction continue each other

using Eigen::Vector3d;

// A field's box in world coordinates, with its outlet and inlet faces.
struct Box {
    graph::FieldId field;
    Vector3d c, half;            // centre, half extents (local)
    Eigen::Matrix3d r;           // local -> world
    bool source = false;         // moves things: it has an outlet
    int axis = 0;                // local axis (0 x, 1 y) of its flow
    double sign = 1;             // the outlet is at +half[axis] (1) or -half[axis] (-1)
    Vector3d n, lat;             // world: the outlet face's normal, the lateral axis
    double half_width = 0;       // half the face's width
    Vector3d outlet;             // middle of the outlet face's bottom edge
    Vector3d inlet_a, inlet_b;   // the inlet face's bottom edge
    Vector3d in_n, in_lat;       // world: the flow's direction at the inlet, its lateral axis (a
                                 // straight box's: n and lat; a turning one's: where its arc enters)

    Vector3d local(const Vector3d& w) const { return r.transpose() * (w - c); }
    Vector3d world(const Vector3d& l) const { return c + r * l; }
};

// A turning field (Field::radius): its lane is the arc of that radius about its pivot, entering
// and leaving its box where the arc crosses the box's sides (in the sense it turns); the lane's
// half width is the box's reach on either side of the arc there, the nearer. A turntable (its
// arc wholly inside) delivers nowhere: no outlet.
void turn_box(const graph::Field& f, Box& b) {
    const Vector3d pivot(f.pivot[0], f.pivot[1], f.pivot[2]);
    const double R = f.radius, s = f.speed < 0 ? -1 : 1;
    auto at = [&](double a) { return Vector3d(pivot.x() + R * std::cos(a), pivot.y() + R * std::sin(a), 0); };
    auto inside = [&](double a) {
        const Vector3d p = at(a);
        return std::abs(p.x()) <= b.half.x() && std::abs(p.y()) <= b.half.y();
    };
    constexpr int kSteps = 720;
    const double step = 2 * M_PI / kSteps;
    // The crossing between angle a (inside or not) and a + s·step, found to 1e-9 rad.
    auto cross = [&](double a) {
        double lo = a, hi = a + s * step;
        const bool in = inside(lo);
        for (int k = 0; k < 60; ++k) {
            const double mid = (lo + hi) / 2;
            (inside(mid) == in ? lo : hi) = mid;
        }
        return (lo + hi) / 2;
    };
    double out = NAN, in = NAN;
    for (int k = 0; k < kSteps; ++k) {
        const double a = s * k * step;
        const bool here = inside(a), next = inside(a + s * step);
        if (here && !next && std::isnan(out)) out = cross(a);
        if (!here && next && std::isnan(in)) in = cross(a);
    }
    if (std::isnan(out) || std::isnan(in)) {
        b.source = false;
        return;
    }
    // The flow's direction at angle a (the tangent, in the sense it turns) and the radial axis.
    auto tangent = [&](double a) { return Vector3d(-s * std::sin(a), s * std::cos(a), 0); };
    auto radial = [&](double a) { return Vector3d(std::cos(a), std::sin(a), 0); };
    // How far the box reaches from the arc's point at angle a along the radial axis, the nearer side.
    auto half_width = [&](double a) {
        const Vector3d p = at(a), r = radial(a);
        double w = HUGE_VAL;
        for (double dir : {-1.0, 1.0}) {
            double reach = HUGE_VAL;
            for (int i = 0; i < 2; ++i)
                if (std::abs(r[i]) > 1e-12) reach = std::min(reach, (dir * (r[i] > 0 ? 1 : -1) * b.half[i] - p[i]) / (dir * r[i]));
            w = std::min(w, reach);
        }
        return std::max(w, 0.0);
    };
    b.source = f.speed != 0 && !f.body.valid();
    b.n = b.r * tangent(out);
    b.lat = b.r * radial(out);
    b.half_width = half_width(out);
    Vector3d o = at(out);
    o.z() = -b.half.z();
    b.outlet = b.world(o);
    Vector3d i = at(in);
    i.z() = -b.half.z();
    const double hw_in = half_width(in);
    b.inlet_a = b.world(i - hw_in * radial(in));
    b.inlet_b = b.world(i + hw_in * radial(in));
    b.in_n = b.r * tangent(in);
    b.in_lat = b.r * radial(in);
}

Box make_box(const graph::Graph& g, graph::FieldId i) {
    const graph::Field& f = g.fields[i];
    Box b;
    b.field = i;
    b.c = Vector3d(f.pose.p[0], f.pose.p[1], f.pose.p[2]);
    b.half = Vector3d(f.extent[0], f.extent[1], f.extent[2]) / 2;
    b.r = Eigen::Quaterniond(f.pose.q[3], f.pose.q[0], f.pose.q[1], f.pose.q[2]).normalized().toRotationMatrix();
    const Vector3d d = Vector3d(f.dir[0], f.dir[1], f.dir[2]) * (f.speed < 0 ? -1.0 : 1.0);
    b.axis = std::abs(d.y()) > std::abs(d.x()) ? 1 : 0;
    b.sign = d[b.axis] < 0 ? -1 : 1;
    // A field on a body moves with it; one that pulls mostly up or down is a lift, not a lane.
    b.source = f.speed != 0 && !f.body.valid() && std::abs(d.z()) < std::abs(d[b.axis]);
    const int other = 1 - b.axis;
    Vector3d e = Vector3d::Zero();
    e[b.axis] = b.sign;
    b.n = b.r * e;
    e = Vector3d::Zero();
    e[other] = 1;
    b.lat = b.r * e;
    b.half_width = b.half[other];
    Vector3d o = Vector3d::Zero();
    o[b.axis] = b.sign * b.half[b.axis];
    o.z() = -b.half.z();
    b.outlet = b.world(o);
    Vector3d ia = -o, ib;
    ia.z() = -b.half.z();
    ib = ia;
    ia[other] = -b.half[other];
    ib[other] = b.half[other];
    b.inlet_a = b.world(ia);
    b.inlet_b = b.world(ib);
    b.in_n = b.n, b.in_lat = b.lat;
    if (f.radius > 0) turn_box(f, b);
    return b;
}

Vector3d nearest_on_segment(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
    const Vector3d ab = b - a;
    const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    return a + t * ab;
}

// The boxes near a point, for the two searches below (each would otherwise look at every box
// for every outlet: 75 % of compiling 166 lines of the bottling plant). A box is listed in
// every cell of a grid over the ground (x, y) that the square about its centre of half side
// reach(b) = |half| + kCapture + the widest outlet's half width meets; every box the searches
// can accept for a point lies within that of the point, so the point's own cell lists all of
// them, in id order, which is the order the searches break their ties in. A box that would
// cover more than kMaxCells cells (a floor's field) is listed once, with the boxes near
// every point.
class Grid {
public:
    static constexpr double kCell = 0.5;  // m
    static constexpr double kMaxCells = 4096;

    explicit Grid(const graph::IdVector<graph::FieldId, Box>& boxes) {
        double widest = 0;
        for (const Box& b : boxes)
            if (b.source) widest = std::max(widest, b.half_width);
        for (graph::FieldId i : boxes.ids()) {
            const Box& b = boxes[i];
            const double r = b.half.norm() + kCapture + widest;
            const double side = std::floor(2 * r / kCell) + 2;
            if (side * side > kMaxCells) {
                big_.push_back(i);
                continue;
            }
            const int64_t x0 = cell(b.c.x() - r), x1 = cell(b.c.x() + r);
            const int64_t y0 = cell(b.c.y() - r), y1 = cell(b.c.y() + r);
            for (int64_t x = x0; x <= x1; ++x)
                for (int64_t y = y0; y <= y1; ++y) cells_[key(x, y)].push_back(i);
        }
    }
    // The boxes whose reach may hold p, in id order.
    const std::vector<graph::FieldId>& near(const Vector3d& p) {
        const auto it = cells_.find(key(cell(p.x()), cell(p.y())));
        const std::vector<graph::FieldId>& here = it == cells_.end() ? none_ : it->second;
        if (big_.empty()) return here;
        found_.clear();
        std::merge(here.begin(), here.end(), big_.begin(), big_.end(), std::back_inserter(found_));
        return found_;
    }

private:
    static int64_t cell(double v) { return static_cast<int64_t>(std::floor(v / kCell)); }
    // Unique for cells within ±2^31 (a billion metres); beyond, two cells may share a list,
    // which only adds candidates.
    static uint64_t key(int64_t x, int64_t y) {
        return (static_cast<uint64_t>(static_cast<uint32_t>(x)) << 32) | static_cast<uint32_t>(y);
    }
    std::unordered_map<uint64_t, std::vector<graph::FieldId>> cells_;
    std::vector<graph::FieldId> big_, found_, none_;
};

std::string cm(double m) { return fmt::format("{:.1f} cm", m * 100); }

std::string where(const Vector3d& p) { return fmt::format("({:.3f}, {:.3f}, {:.3f}) m", p.x(), p.y(), p.z()); }

}  // namespace

void Elaborator::check_conveyor_ends() {
    if (g_.fields.size() < 2) return;
    // Files of the standard library: a conveyor is named by the instance the plant's own files
    // declare (the Curve, not its ninth piece; the Belt, not its field), where its placement is.
    std::set<int32_t> std_files;
    std::error_code ec;
    const auto std_dir = std::filesystem::weakly_canonical(prog_.stdlib_dir, ec).generic_string();
    for (const auto& m : prog_.modules)
        if (!std_dir.empty() && m.ast && m.key.rfind(std_dir + "/", 0) == 0) std_files.insert(m.ast->file);
    auto declared = [&](graph::FieldId field) {
        const graph::CompId comp = g_.fields[field].comp;
        graph::DoId d = g_.comps[comp].owner;
        if (!d.valid() || !g_.dos[d].parent.valid()) {  // the plant's (or the type's) own field
            const auto cs = comp_spans_.find(comp);
            return cs != comp_spans_.end() ? cs->second : Span{};
        }
        while (d.valid() && std_files.count(do_spans_[d].file) && g_.dos[d].parent.valid())
            d = g_.dos[d].parent;
        return d.valid() ? do_spans_[d] : Span{};
    };
    auto path = [&](graph::FieldId field) {
        const auto& c = g_.comps[g_.fields[field].comp];
        const std::string owner(g_.str(g_.dos[c.owner].path));
        const std::string name(g_.str(c.name));
        return owner.empty() ? name : owner + "." + name;
    };

    graph::IdVector<graph::FieldId, Box> boxes;  // a field's box by its id
    for (graph::FieldId i : ids_of(g_.fields)) boxes.push_back(make_box(g_, i));
    Grid grid(boxes);
    std::set<std::tuple<int32_t, uint32_t, int32_t, uint32_t>> reported;  // once per pair of declarations
    auto report = [&](const Box& a, const Box& b, std::string message, std::string why) {
        const Span sa = declared(a.field), sb = declared(b.field);
        if (!reported.insert({sa.file, sa.begin, sb.file, sb.begin}).second) return;
        auto& d = sink_.report(DiagId::ConveyorEndsMiss, sa, std::move(message));
        d.notes.push_back({sb, fmt::format("'{}' is declared here", path(b.field))});
        d.notes.push_back({{}, std::move(why)});
    };

    for (const Box& a : boxes) {
        if (!a.source) continue;
        const Vector3d ahead = a.outlet + kGap * a.n;
        const Box* on = nullptr;     // a box the outlet runs onto, level
        const Box* step = nullptr;   // one it runs onto with a step (the smallest)
        double step_h = 0;
        for (graph::FieldId k : grid.near(ahead)) {
            const Box& b = boxes[k];
            if (b.field == a.field || g_.fields[b.field].body.valid()) continue;
            const Vector3d l = b.local(ahead);
            if (std::abs(l.x()) > b.half.x() || std::abs(l.y()) > b.half.y()) continue;
            const double h = l.z() + b.half.z();  // the outlet's height above b's bottom
            if (std::abs(h) <= kGap) {
                // Level: a lane that runs on in about the same direction must line up with it.
                if (!on || (std::abs(a.n.dot(b.in_n)) >= kParallel && std::abs(a.n.dot(on->in_n)) < kParallel)) on = &b;
            } else if (std::abs(h) <= kCapture && (!step || std::abs(h) < std::abs(step_h))) {
                step = &b;
                step_h = h;
            }
        }
        if (on) {
            const Box& b = *on;
            if (std::abs(a.n.dot(b.in_n)) < kParallel) continue;  // a transfer across: its own rails guide
            const double aside = std::abs((a.outlet - (b.inlet_a + b.inlet_b) / 2).dot(b.in_lat));
            const double slack = std::abs(a.half_width - b.half_width);
            if (aside > slack + kAside)
                report(a, b,
                       fmt::format("the end of conveyor '{}' meets '{}' {} off its centre line", path(a.field),
                                   path(b.field), cm(aside - slack)),
                       fmt::format("at {}: lanes that continue each other must line up within {} mm (beyond the "
                                   "difference of their widths), or a rail stands across the way",
                                   where(a.outlet), kAside * 1000));
            continue;
        }
        if (step) {
            report(a, *step,
                   fmt::format("the end of conveyor '{}' meets '{}' with a step of {} ({} is {})", path(a.field),
                               path(step->field), cm(std::abs(step_h)), path(step->field),
                               step_h > 0 ? "lower" : "higher"),
                   fmt::format("at {}: bands that meet must be level within {} mm", where(a.outlet), kGap * 1000));
            continue;
        }
        // Nothing under the outlet: the nearest conveyor that starts ahead of it within reach,
        // either in the way ahead (the strip as wide as the outlet, 20 cm long) or, running on
        // in about the same direction, with its start's edge within 20 cm.
        const Box* near = nullptr;
        Vector3d miss = Vector3d::Zero();  // from the outlet to where the other conveyor starts
        double near_d = kCapture + 1e-9;
        for (graph::FieldId k : grid.near(a.outlet)) {
            const Box& b = boxes[k];
            if (b.field == a.field || g_.fields[b.field].body.valid()) continue;
            if ((b.c - a.outlet).norm() > kCapture + a.half_width + b.half.norm()) continue;
            const Vector3d l0 = b.local(a.outlet);
            if (std::abs(l0.x()) <= b.half.x() + 1e-9 && std::abs(l0.y()) <= b.half.y() + 1e-9) continue;  // still in it
            if (std::abs(a.n.dot(b.in_n)) >= kParallel) {
                const Vector3d y = nearest_on_segment(a.outlet, b.inlet_a, b.inlet_b);
                const double dist = (y - a.outlet).norm();
                // Its start's middle, for the message: how far ahead, aside and up.
                if (dist < near_d && (y - a.outlet).dot(a.n) >= -kGap)
                    near = &b, miss = (b.inlet_a + b.inlet_b) / 2 - a.outlet, near_d = dist;
                continue;
            }
            // Where across the strip (five lines) b's box is first met, to within 0.1 mm.
            auto met = [&](double s, double& h) {
                for (int k = -2; k <= 2; ++k) {
                    const Vector3d l = b.local(a.outlet + s * a.n + (a.half_width - kAside) * (k / 2.0) * a.lat);
                    h = l.z() + b.half.z();
                    if (std::abs(l.x()) <= b.half.x() && std::abs(l.y()) <= b.half.y() && std::abs(h) <= kCapture)
                        return true;
                }
                return false;
            };
            double h = 0;
            for (double s = kGap; s < near_d; s += 2.5e-3) {
                if (!met(s, h)) continue;
                double lo = s - 2.5e-3;
                while (s - lo > 1e-4) {
                    const double mid = (lo + s) / 2;
                    if (met(mid, h)) s = mid;
                    else lo = mid;
                }
                met(s, h);
                near = &b, near_d = s, miss = s * a.n - h * b.r.col(2);
                break;
            }
        }
        if (!near) continue;
        const Vector3d up = a.r.col(2);
        const double h = miss.dot(up);
        report(a, *near,
               fmt::format("the end of conveyor '{}' misses '{}', which starts {} ahead, {} aside and {}",
                           path(a.field), path(near->field), cm(miss.dot(a.n)), cm(std::abs(miss.dot(a.lat))),
                           std::abs(h) <= kGap ? "level" : cm(std::abs(h)) + (h < 0 ? " lower" : " higher")),
               fmt::format("at {}: a conveyor that starts within {} of another's end is taken to continue it; "
                           "move it to start within {} mm of that end, in line and level with it",
                           where(a.outlet), cm(kCapture), kGap * 1000));
    }
}

}  // namespace plant::sema
