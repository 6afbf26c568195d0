// A register map over the bottling plant's slots, built in code until the link kind
// declares one in the plant file: the unit tests' and the mbpoll harness's map.
//
//   DI 0      line[0].s2.sw.reader.volume.on_stay   1 while a bottle is in S2's ID reader
//   IR 0      line[0].s2.sw.reader.volume.count     bottles in it (int16)
//   IR 1      line[0].s2.seen                        steps a bottle entered it in (count)
//   IR 2      line[0].b1.speed_now                   mm/s (scaled x 1000)
//   IR 3-4    line[0].b1.speed_now                   m/s (float32)
//   IR 10-17  line[0].s2.id                          the last bar code read (16 chars)
//   coil 0    line[0].b1.stop      coil 1  line[0].b1.go
//   HR 0      line[0].b1.set_speed (mm/s)  HR 1  line[0].s2.to_working (non-zero fires)
#pragma once

#include "engine/events.h"
#include "plc/map.h"

#include <string>

namespace plant::test {

inline bool bottling_map(const graph::Graph& g, plc::Map& m, std::string& error) {
    using plc::Encoding;
    using plc::Table;
    const engine::SlotIndex idx = engine::slot_index(g);
    const plc::EntrySpec specs[] = {
        {Table::DiscreteInput, 0, "line[0].s2.sw.reader.volume.on_stay", Encoding::Bit},
        {Table::InputRegister, 0, "line[0].s2.sw.reader.volume.count", Encoding::Int16},
        {Table::InputRegister, 1, "line[0].s2.seen", Encoding::Count},
        {Table::InputRegister, 2, "line[0].b1.speed_now", Encoding::Scaled, 1000, "mm/s"},
        {Table::InputRegister, 3, "line[0].b1.speed_now", Encoding::Float32},
        {Table::InputRegister, 10, "line[0].s2.id", Encoding::String, 1, "", 8},
        {Table::Coil, 0, "line[0].b1.stop", Encoding::Bit},
        {Table::Coil, 1, "line[0].b1.go", Encoding::Bit},
        {Table::HoldingRegister, 0, "line[0].b1.set_speed", Encoding::Scaled, 1000, "mm/s"},
        {Table::HoldingRegister, 1, "line[0].s2.to_working", Encoding::Bit},
    };
    m.entries.clear();
    for (const plc::EntrySpec& s : specs) {
        plc::Entry e;
        if (!plc::make_entry(idx, s, e, error)) return false;
        m.entries.push_back(std::move(e));
    }
    for (const plc::MapError& e : plc::check_map(m, g)) {
        error = e.message;
        return false;
    }
    return true;
}

}  // namespace plant::test
