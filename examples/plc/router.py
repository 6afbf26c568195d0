#!/usr/bin/python3
"""The routing control of the bottling line as a PLC program outside the plant.

plants/bottling_plc.plant declares the register map (`plant info --modbus` prints it): for
switch k (S1..S5, k = 0..4) input register k counts the bottles its ID reader saw and
input registers 10 + 8k hold the code read last; coil k sets the switch to its lane, coil
10 + k straight on. Exit k: input register 50 + k counts the bottles it took, 60 + 8k the
code of the last one. Lane k is the letter A..E the code starts with.

The rule (the plant's own RoutedSwitch, docs/stdlib.md): a bottle goes into a lane when
its code names that lane and it is filled and capped. New bottles are set down just before
S5 and pass it once before they reach the filling and capping stations, so a bottle is due
at S1..S4 always and at S5 from its second pass on: the program remembers the codes S5 saw.

    /usr/bin/python3 router.py PORT                    poll every 5 ms until the plant stops
    /usr/bin/python3 router.py PORT --lockstep STEPS  drive `plant run --lockstep`: grant STEPS steps, two
                                         at a time, scanning after each grant
    ... --lockstep STEPS --fault ENTRY FROM TO      and force map entry ENTRY open circuit from
                                         step FROM to step TO (the link's fault block)

It prints one line per bottle an exit took and a summary; exit status 1 if a bottle went
into a lane its code does not name.
"""
import argparse
import sys
import time

from pymodbus.client import ModbusTcpClient
from pymodbus.exceptions import ModbusException, ModbusIOException

SEEN, IDS, EXIT_COUNT, EXIT_IDS = 0, 10, 50, 60
TO_LANE, STRAIGHT = 0, 10
ADVANCE, STEPS = 60000, 60000  # the link's control block (docs/plc.md)
FAULTS, FAULT_STRIDE, RELEASE, OPEN = 60100, 4, 0, 2
LANES = "ABCDE"


def text(registers):
    """A string entry: two ASCII bytes per register, high byte first, NUL padded."""
    raw = b"".join(bytes([r >> 8, r & 0xFF]) for r in registers)
    return raw.split(b"\0", 1)[0].decode("ascii", "replace")


class Router:
    def __init__(self, client):
        self.client = client
        self.seen = None  # the readers' counts at the last scan
        self.taken = None  # the exits' counts
        self.passed_s5 = set()  # codes S5 has seen: those bottles are on their second pass
        self.routed = 0
        self.commissioned = {lane: 0 for lane in LANES}
        self.wrong = 0

    def read(self, address, count):
        r = self.client.read_input_registers(address, count)
        if isinstance(r, ModbusIOException):
            raise r  # the connection is gone (the plant's run ended): main() stops there
        if r.isError():
            sys.exit(f"router: reading input registers {address}..{address + count - 1}: {r}")
        return r.registers

    def scan(self):
        # Three blocks: a read may not span the unmapped addresses between them.
        regs = self.read(SEEN, 5) + [0] * 5 + self.read(IDS, 45) + [0] * 5 + self.read(EXIT_IDS, 40)
        seen, taken = regs[SEEN:SEEN + 5], regs[EXIT_COUNT:EXIT_COUNT + 5]
        if self.seen is None:
            self.seen, self.taken = seen, taken
        for k in range(5):
            if seen[k] != self.seen[k]:
                code = text(regs[IDS + 8 * k:IDS + 8 * k + 8])
                due = k < 4 or code in self.passed_s5
                if k == 4:
                    self.passed_s5.add(code)
                lane = due and code[:1] == LANES[k]
                self.client.write_coil(TO_LANE + k if lane else STRAIGHT + k, True)
                self.routed += lane
            if taken[k] != self.taken[k]:
                code = text(regs[EXIT_IDS + 8 * k:EXIT_IDS + 8 * k + 8])
                self.commissioned[LANES[k]] += (taken[k] - self.taken[k]) & 0xFFFF
                ok = code[:1] == LANES[k]
                self.wrong += not ok
                print(f"router: exit {LANES[k]} took {code}{'' if ok else '  WRONG LANE'}", flush=True)
        self.seen, self.taken = seen, taken

    def steps(self):
        r = self.read(STEPS, 2)
        return (r[0] << 16) | r[1]


def main():
    args = argparse.ArgumentParser(description="The bottling line's routing as a PLC program.")
    args.add_argument("port", type=int)
    args.add_argument("--lockstep", type=int, default=0, metavar="STEPS", help="grant STEPS steps, two at a time")
    args.add_argument("--fault", type=int, nargs=3, metavar=("ENTRY", "FROM", "TO"),
                      help="lock-step: force map entry ENTRY open circuit through the link's fault block "
                           "from step FROM, release it at step TO")
    a = args.parse_args()
    port, lockstep = a.port, a.lockstep
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=5)
    deadline = time.monotonic() + 30
    while not client.connect():
        if time.monotonic() > deadline:
            sys.exit("router: cannot connect")
        time.sleep(0.2)
    router = Router(client)
    try:
        if lockstep:
            done = router.steps()
            router.scan()
            while done < lockstep:
                if a.fault and done in (a.fault[1], a.fault[2]):
                    mode = OPEN if done == a.fault[1] else RELEASE
                    client.write_register(FAULTS + FAULT_STRIDE * a.fault[0], mode)
                    print(f"router: step {done}: entry {a.fault[0]} {'open' if mode == OPEN else 'released'}")
                n = min(2, lockstep - done)
                client.write_register(ADVANCE, n)
                if done + n == lockstep:
                    break  # the run ends after its last step: nothing left to scan
                done += n
                limit = time.monotonic() + 30
                while router.steps() < done:
                    if time.monotonic() > limit:
                        sys.exit(f"router: stuck at {router.steps()} steps")
                router.scan()
        else:
            while True:
                router.scan()
                time.sleep(0.005)
    except (OSError, ModbusException):
        pass  # the plant stopped: the connection is gone
    total = sum(router.commissioned.values())
    print(f"router: {router.routed} bottles sent into a lane; exits took {total} "
          f"({', '.join(f'{k} {v}' for k, v in router.commissioned.items())}); {router.wrong} in a wrong lane")
    client.close()
    sys.exit(1 if router.wrong else 0)


if __name__ == "__main__":
    main()
