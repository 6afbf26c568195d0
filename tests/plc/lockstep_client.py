#!/usr/bin/python3
# A lock-step client for `plant run --lockstep` (docs/plc.md): grants steps in chunks of
# `chunk` until `total` steps are granted, waiting for each chunk but the last (bounded; the
# run ends by itself after the last one), with Debian's pymodbus.
#   lockstep_client.py PORT TOTAL CHUNK
import sys
import time

from pymodbus.client import ModbusTcpClient

ADVANCE, STEPS, LOCKSTEP = 60000, 60000, 60004
port, total, chunk = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
client = ModbusTcpClient("127.0.0.1", port=port, timeout=5)
if not client.connect():
    sys.exit("lockstep client: cannot connect")


def steps():
    r = client.read_input_registers(STEPS, 2)
    if r.isError():
        sys.exit(f"lockstep client: {r}")
    return (r.registers[0] << 16) | r.registers[1]


if client.read_input_registers(LOCKSTEP, 1).registers[0] != 1:
    sys.exit("lockstep client: the plant is not in lock-step")
done = steps()
while done < total:
    n = min(chunk, total - done)
    if client.write_register(ADVANCE, n).isError():
        sys.exit("lockstep client: the advance was refused")
    if done + n == total:
        done = total
        break
    deadline = time.monotonic() + 30
    while steps() < done + n:
        if time.monotonic() > deadline:
            sys.exit(f"lockstep client: stuck at {steps()} steps")
        time.sleep(0.002)
    done += n
print(f"lockstep client: granted {done} steps")
client.close()
