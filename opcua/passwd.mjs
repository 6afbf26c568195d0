#!/usr/bin/env node
// Writes a users-file line for an OPC UA link (users.mjs): the password is read from stdin
// (one line; typed without echo on a terminal), never given on the command line.
//
//   node opcua/passwd.mjs operator >> plant.users
import { hashLine } from "./users.mjs";

const name = process.argv[2];
if (!name || !/^[^\s:]+$/.test(name) || process.argv.length > 3) {
    process.stderr.write("usage: node opcua/passwd.mjs NAME  (the password on stdin; a line NAME:scrypt:SALT:HASH on stdout)\n");
    process.exit(2);
}

async function readPassword() {
    const stdin = process.stdin;
    if (stdin.isTTY) {
        process.stderr.write(`password for ${name}: `);
        stdin.setRawMode(true);
    }
    let text = "";
    for await (const chunk of stdin) {
        text += chunk.toString("utf8");
        if (stdin.isTTY && /[\r\n\u0003\u0004]/.test(text)) break;
    }
    if (stdin.isTTY) {
        stdin.setRawMode(false);
        process.stderr.write("\n");
        if (text.includes("\u0003")) process.exit(130);
    }
    return text.split(/[\r\n\u0004]/)[0];
}

const password = await readPassword();
if (!password) {
    process.stderr.write("passwd: an empty password\n");
    process.exit(1);
}
process.stdout.write(hashLine(name, password) + "\n");
process.exit(0);
