// The Plant extension: starts `plant lsp` (setting plant.server.path) for .plant files.
'use strict';
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

async function activate(context) {
  const config = vscode.workspace.getConfiguration('plant');
  const command = config.get('server.path') || 'plant';
  const args = ['lsp', ...(config.get('server.args') || [])];
  client = new LanguageClient(
    'plant',
    'Plant language server',
    { run: { command, args }, debug: { command, args } },
    { documentSelector: [{ scheme: 'file', language: 'plant' }] },
  );
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration('plant.server'))
        vscode.window.showInformationMessage('Plant: reload the window to restart the language server with the new settings.');
    }),
  );
  await client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
