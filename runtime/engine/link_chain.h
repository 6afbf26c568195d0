// Several external links on one run (a Modbus PLC and an OPC UA SCADA at once): one
// RunLink (run.h) that calls each in turn. At most one of them may be in lock-step; the
// others' wait() returns at once.
#pragma once

#include "engine/run.h"

#include <vector>

namespace plant::engine {

class LinkChain final : public RunLink {
public:
    explicit LinkChain(std::vector<RunLink*> links) : links_(std::move(links)) { applied_.reserve(1024); }
    bool wait(std::string& error) override {
        for (RunLink* l : links_)
            if (!l->wait(error)) return false;
        return true;
    }
    void before_step(Engine& e) override {
        applied_.clear();
        for (RunLink* l : links_) {
            l->before_step(e);
            const std::span<const Event* const> a = l->applied();
            applied_.insert(applied_.end(), a.begin(), a.end());  // within its capacity but for huge maps
        }
    }
    std::span<const Event* const> applied() const override { return applied_; }
    void after_step(const Engine& e) override {
        for (RunLink* l : links_) l->after_step(e);
    }
    std::vector<graph::SlotId> forceable() const override {
        std::vector<graph::SlotId> out;
        for (const RunLink* l : links_) {
            const std::vector<graph::SlotId> f = l->forceable();
            out.insert(out.end(), f.begin(), f.end());
        }
        return out;
    }

private:
    std::vector<RunLink*> links_;
    std::vector<const Event*> applied_;
};

}  // namespace plant::engine
