#include "plc/frames.h"

#include <stdexcept>

namespace plant::plc {

namespace {

constexpr int kHeader = 7;  // MBAP: transaction id, protocol id, length, unit id

Table table_of_read(int fc) {
    switch (fc) {
    case MODBUS_FC_READ_COILS: return Table::Coil;
    case MODBUS_FC_READ_DISCRETE_INPUTS: return Table::DiscreteInput;
    case MODBUS_FC_READ_HOLDING_REGISTERS: return Table::HoldingRegister;
    default: return Table::InputRegister;
    }
}

}  // namespace

int frame_length(const uint8_t* d, size_t n) {
    if (n >= 4 && (d[2] != 0 || d[3] != 0)) return -1;
    if (n < kHeader) return 0;
    const int len = (d[4] << 8) | d[5];  // unit id + PDU
    if (len < 2 || len > MODBUS_TCP_MAX_ADU_LENGTH - 6) return -1;
    return n < size_t(6 + len) ? 0 : 6 + len;
}

Tables::Tables(const Map& map) : map_(map) {
    m_ = modbus_mapping_new(65536, 65536, 65536, 65536);
    if (!m_) throw std::runtime_error("modbus_mapping_new: out of memory");
    for (auto& o : owner_) o.assign(65536, kNone);
    for (size_t i = 0; i < map_.entries.size(); ++i) {
        const Entry& e = map_.entries[i];
        for (int32_t a = e.address; a < e.address + width(e) && a >= 0 && a < 65536; ++a)
            owner_[size_t(e.table)][size_t(a)] = int32_t(i);
    }
    owner_[size_t(Table::HoldingRegister)][size_t(kAdvance)] = kControl;
    for (int32_t a = kStatusSteps; a < kStatusSteps + kStatusCount; ++a) owner_[size_t(Table::InputRegister)][size_t(a)] = kControl;
    const size_t faults = std::min(map_.entries.size(), size_t(kMaxEntries));
    for (size_t a = size_t(kFaultBase); a < size_t(kFaultBase) + kFaultStride * faults; ++a)
        owner_[size_t(Table::HoldingRegister)][a] = kControl;
}

Tables::~Tables() { modbus_mapping_free(m_); }

bool Tables::reply_exception(modbus_t* ctx, const uint8_t* frame, int code) {
    ++exceptions_;
    return modbus_reply_exception(ctx, frame, unsigned(code)) > 0;
}

int Tables::check_range(Table t, int32_t address, int32_t count) const {  // coils and holding registers: read and write alike
    if (address + count > 65536) return MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;
    for (int32_t a = address; a < address + count; ++a)
        if (at(t, a) == kNone) return MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;
    return 0;
}

int Tables::check_control_writes(int32_t address, int32_t count, const uint8_t* values) const {
    for (int32_t i = 0; i < count; ++i) {
        const int32_t a = address + i;
        if (a < kFaultBase || (a - kFaultBase) % kFaultStride != 0) continue;
        const size_t entry = size_t((a - kFaultBase) / kFaultStride);
        const int mode = (values[2 * i] << 8) | values[2 * i + 1];
        const graph::SlotType type = map_.entries[entry].type;
        if (mode > 3 || (mode == 3 && type != graph::SlotType::Bool) || (mode == 1 && type == graph::SlotType::String))
            return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
    }
    return 0;
}

void Tables::note_writes(Table t, int32_t address, int32_t count, std::vector<Change>& changes) const {
    for (int32_t a = address; a < address + count; ++a) {
        const int32_t o = at(t, a);
        if (o >= 0) {
            if (changes.empty() || changes.back().kind != Change::Value || changes.back().entry != o)
                changes.push_back({Change::Value, o, 0});
        } else if (t == Table::HoldingRegister && a == kAdvance) {
            changes.push_back({Change::Advance, -1, m_->tab_registers[kAdvance]});
        } else if (t == Table::HoldingRegister && a >= kFaultBase && (a - kFaultBase) % kFaultStride == 0) {
            changes.push_back({Change::Fault, (a - kFaultBase) / kFaultStride, 0});
        }
    }
}

bool Tables::handle(modbus_t* ctx, const uint8_t* frame, int length, std::vector<Change>& changes) {
    const uint8_t* pdu = frame + kHeader;
    const int n = length - kHeader;  // PDU bytes, at least the function code
    const int fc = pdu[0];
    auto u16 = [&](int off) { return int32_t((pdu[off] << 8) | pdu[off + 1]); };
    auto bad = [&](int code) { return reply_exception(ctx, frame, code); };
    constexpr int kValue = MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
    switch (fc) {
    case MODBUS_FC_READ_COILS:
    case MODBUS_FC_READ_DISCRETE_INPUTS:
    case MODBUS_FC_READ_HOLDING_REGISTERS:
    case MODBUS_FC_READ_INPUT_REGISTERS: {
        if (n != 5) return bad(kValue);
        const int32_t address = u16(1), count = u16(3);
        const bool bits = fc == MODBUS_FC_READ_COILS || fc == MODBUS_FC_READ_DISCRETE_INPUTS;
        if (count < 1 || count > (bits ? MODBUS_MAX_READ_BITS : MODBUS_MAX_READ_REGISTERS)) return bad(kValue);
        if (int c = check_range(table_of_read(fc), address, count)) return bad(c);
        return modbus_reply(ctx, frame, length, m_) > 0;
    }
    case MODBUS_FC_WRITE_SINGLE_COIL:
    case MODBUS_FC_WRITE_SINGLE_REGISTER: {
        if (n != 5) return bad(kValue);
        const int32_t address = u16(1), value = u16(3);
        const bool coil = fc == MODBUS_FC_WRITE_SINGLE_COIL;
        if (coil && value != 0 && value != 0xff00) return bad(kValue);
        const Table t = coil ? Table::Coil : Table::HoldingRegister;
        if (int c = check_range(t, address, 1)) return bad(c);
        if (!coil)
            if (int c = check_control_writes(address, 1, pdu + 3)) return bad(c);
        if (modbus_reply(ctx, frame, length, m_) <= 0) return false;
        note_writes(t, address, 1, changes);
        return true;
    }
    case MODBUS_FC_WRITE_MULTIPLE_COILS:
    case MODBUS_FC_WRITE_MULTIPLE_REGISTERS: {
        if (n < 6) return bad(kValue);
        const bool coil = fc == MODBUS_FC_WRITE_MULTIPLE_COILS;
        const int32_t address = u16(1), count = u16(3), bytes = pdu[5];
        if (count < 1 || count > (coil ? MODBUS_MAX_WRITE_BITS : MODBUS_MAX_WRITE_REGISTERS)) return bad(kValue);
        if (bytes != (coil ? (count + 7) / 8 : 2 * count) || n != 6 + bytes) return bad(kValue);
        const Table t = coil ? Table::Coil : Table::HoldingRegister;
        if (int c = check_range(t, address, count)) return bad(c);
        if (!coil)
            if (int c = check_control_writes(address, count, pdu + 6)) return bad(c);
        if (modbus_reply(ctx, frame, length, m_) <= 0) return false;
        note_writes(t, address, count, changes);
        return true;
    }
    case MODBUS_FC_WRITE_AND_READ_REGISTERS: {
        if (n < 10) return bad(kValue);
        const int32_t read = u16(1), reads = u16(3), write = u16(5), writes = u16(7), bytes = pdu[9];
        if (reads < 1 || reads > MODBUS_MAX_WR_READ_REGISTERS || writes < 1 || writes > MODBUS_MAX_WR_WRITE_REGISTERS ||
            bytes != 2 * writes || n != 10 + bytes)
            return bad(kValue);
        if (int c = check_range(Table::HoldingRegister, write, writes)) return bad(c);
        if (int c = check_range(Table::HoldingRegister, read, reads)) return bad(c);
        if (int c = check_control_writes(write, writes, pdu + 10)) return bad(c);
        if (modbus_reply(ctx, frame, length, m_) <= 0) return false;
        note_writes(Table::HoldingRegister, write, writes, changes);
        return true;
    }
    default: return bad(MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
    }
}

}  // namespace plant::plc
