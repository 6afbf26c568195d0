// The OPC UA link's security off 127.0.0.1 (security_test.sh serves the plant on 127.0.0.2,
// which the link serves as any address but 127.0.0.1): what each client gets, as one JSON line.
//   node security_test.mjs URL CLIENT_PKI SERVER_PKI USER PASSWORD
import fs from "node:fs";
import path from "node:path";
import ua from "./ua.mjs";

const { OPCUAClient, OPCUACertificateManager, MessageSecurityMode, SecurityPolicy, AttributeIds, DataType, UserTokenType } = ua;
const [url, clientPki, serverPki, user, password] = process.argv.slice(2);
const out = {};
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
const why = (err) => (String(err?.message ?? err).match(/Bad\w+/) || [String(err?.message ?? err).split("\n")[0]])[0];

const certificates = new OPCUACertificateManager({ rootFolder: clientPki, automaticallyAcceptUnknownCertificate: true });
await certificates.initialize();

function client(securityMode, securityPolicy) {
    return OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 }, securityMode, securityPolicy,
                                clientCertificateManager: certificates, applicationName: "plant security test",
                                requestedSessionTimeout: 20000 });
}

// What the server offers: each endpoint's policy and mode.
{
    const c = client(MessageSecurityMode.None, SecurityPolicy.None);
    await c.connect(url);
    out.endpoints = (await c.getEndpoints()).map((e) => `${e.securityPolicyUri.split("#")[1]}/${MessageSecurityMode[e.securityMode]}`
                                                        + `/${e.userIdentityTokens.map((t) => UserTokenType[t.tokenType]).join("+")}`);
    await c.disconnect();
}

// A session over SecurityPolicy None: refused.
async function session(mode, policy, identity) {
    const c = client(mode, policy);
    try {
        await c.connect(url);
        const s = await c.createSession(identity);
        return { c, s };
    } catch (err) {
        await c.disconnect().catch(() => {});
        return { error: why(err) };
    }
}
out.none = (await session(MessageSecurityMode.None, SecurityPolicy.None)).error ?? "Good";
// ... and by the server, to a client that skips its library's check: a CreateSession sent on
// a channel with SecurityPolicy None (which the server opens for GetEndpoints only).
{
    const c = client(MessageSecurityMode.None, SecurityPolicy.None);
    await c.connect(url);
    const request = new ua.CreateSessionRequest({ endpointUrl: url, sessionName: "none", requestedSessionTimeout: 10000,
                                                  clientNonce: Buffer.alloc(32, 7), clientDescription: { applicationUri: "urn:plant:test",
                                                  applicationName: { text: "plant security test" }, applicationType: ua.ApplicationType.Client } });
    out.noneByServer = await new Promise((resolve) => c.performMessageTransaction(request, (err, response) =>
        resolve(err ? why(err) : response.responseHeader.serviceResult.name)));
    await c.disconnect();
}

// Basic256Sha256 with a certificate the server does not know: refused, and kept in its
// rejected folder; trusted by moving it to trusted/certs (what docs/plc.md tells an admin).
const secure = () => session(MessageSecurityMode.SignAndEncrypt, SecurityPolicy.Basic256Sha256);
const first = await secure();
out.unknownCertificate = first.error ?? "Good";
if (first.s) await first.c.disconnect();
const rejected = path.join(serverPki, "rejected");
const files = fs.existsSync(rejected) ? fs.readdirSync(rejected).filter((f) => f.endsWith(".pem") || f.endsWith(".der")) : [];
out.rejectedKept = files.length;
fs.mkdirSync(path.join(serverPki, "trusted", "certs"), { recursive: true });
for (const f of files) fs.renameSync(path.join(rejected, f), path.join(serverPki, "trusted", "certs", f));
await sleep(1500);  // the server's certificate manager sees its folders change

const write = (s) => s.write({ nodeId: "ns=2;i=62", attributeId: AttributeIds.Value,
                                 value: { value: { dataType: DataType.Double, value: 400 } } }).then((r) => r.name);
const call = (s) => s.call({ objectId: "ns=2;s=line[0].s1", methodId: "ns=2;i=21", inputArguments: [] }).then((r) => r.statusCode.name);
const read = (s) => s.read({ nodeId: "ns=1;s=Link.Steps", attributeId: AttributeIds.Value }).then((dv) => dv.statusCode.name);

const anonymous = await secure();
out.anonymous = anonymous.error ?? { read: await read(anonymous.s), write: await write(anonymous.s), call: await call(anonymous.s) };
if (anonymous.s) await anonymous.c.disconnect();

const wrong = await session(MessageSecurityMode.SignAndEncrypt, SecurityPolicy.Basic256Sha256,
                            { type: UserTokenType.UserName, userName: user, password: `${password}x` });
out.wrongPassword = wrong.error ?? "Good";
if (wrong.s) await wrong.c.disconnect();

const named = await session(MessageSecurityMode.SignAndEncrypt, SecurityPolicy.Basic256Sha256,
                            { type: UserTokenType.UserName, userName: user, password });
out.user = named.error ?? { read: await read(named.s), write: await write(named.s), call: await call(named.s) };
if (named.s) await named.c.disconnect();

console.log(JSON.stringify(out));
process.exit(0);
