// node-opcua for the test clients: from the server's package folder (opcua/, installed by
// scripts/setup.sh), so that tests/ needs no node_modules of its own.
import { createRequire } from "node:module";

const require = createRequire(new URL("../../opcua/package.json", import.meta.url));
const ua = require("node-opcua");
const quiet = () => {};
ua.setWarningLogger(quiet);  // a client test prints what it checks, not the library's notices
export default ua;
