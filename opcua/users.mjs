// The users file of an OPC UA link (docs/plc.md, "OPC UA", Security): one user a line,
//
//   NAME:scrypt:SALT:HASH
//
// SALT 16 random bytes and HASH scrypt(password, SALT, 32 bytes; N 16384, r 8, p 1), both
// in hex; blank lines and lines starting with # are skipped. `node opcua/passwd.mjs NAME`
// writes such a line. A file of passwords in clear is refused.
import crypto from "node:crypto";
import fs from "node:fs";

const KEY = 32;
const PARAMS = { N: 16384, r: 8, p: 1 };

export function hashLine(name, password) {
    const salt = crypto.randomBytes(16);
    const hash = crypto.scryptSync(password, salt, KEY, PARAMS);
    return `${name}:scrypt:${salt.toString("hex")}:${hash.toString("hex")}`;
}

// The users of `file`: a Map from name to {salt, hash}; throws an Error whose message names
// the file and line of the first problem.
export function loadUsers(file) {
    let text;
    try {
        text = fs.readFileSync(file, "utf8");
    } catch (err) {
        throw new Error(`users file ${file}: ${err.code === "ENOENT" ? "no such file" : err.message}`);
    }
    const users = new Map();
    text.split("\n").forEach((raw, i) => {
        const line = raw.trim();
        if (!line || line.startsWith("#")) return;
        const where = `${file}:${i + 1}`;
        const parts = line.split(":");
        if (parts.length !== 4 || parts[1] !== "scrypt")
            throw new Error(`${where}: expected NAME:scrypt:SALT:HASH (write it with node opcua/passwd.mjs NAME)`);
        const [name, , salt, hash] = parts;
        if (!/^[^\s:]+$/.test(name)) throw new Error(`${where}: a user name without spaces or colons`);
        if (!/^[0-9a-f]{32}$/.test(salt) || !/^[0-9a-f]{64}$/.test(hash))
            throw new Error(`${where}: SALT is 32 and HASH 64 hex digits`);
        if (users.has(name)) throw new Error(`${where}: user '${name}' is given twice`);
        users.set(name, { salt: Buffer.from(salt, "hex"), hash: Buffer.from(hash, "hex") });
    });
    return users;
}

// Whether `password` is `name`'s, without blocking the server's event loop.
export function checkUser(users, name, password, callback) {
    const user = users.get(name);
    const salt = user ? user.salt : crypto.randomBytes(16);  // the same work for an unknown name
    crypto.scrypt(String(password ?? ""), salt, KEY, PARAMS, (err, key) => {
        callback(null, !err && !!user && crypto.timingSafeEqual(key, user.hash));
    });
}
