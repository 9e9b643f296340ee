// A static server for the web viewer: web/ at /, and a folder of exports at /data/:
//   node web/serve.mjs DIR [--port P]
// then open http://localhost:P/?tileset=data/TILES/tileset.json&path=data/PATH.json
// (P defaults to 8000; 0 picks a free one). Prints "serving http://localhost:P/" when ready.
import http from 'node:http';
import { createReadStream } from 'node:fs';
import { stat } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const args = process.argv.slice(2);
const at = args.indexOf('--port');
const port = at >= 0 ? Number(args[at + 1]) : 8000;
const data = args.find((a, i) => !a.startsWith('--') && args[i - 1] !== '--port');
if (!data || !Number.isInteger(port)) {
  console.error('usage: node web/serve.mjs DIR [--port P]');
  process.exit(2);
}
const web = path.dirname(fileURLToPath(import.meta.url));
const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
                '.json': 'application/json', '.glb': 'model/gltf-binary', '.png': 'image/png' };

const server = http.createServer(async (request, response) => {
  const url = decodeURIComponent(new URL(request.url, 'http://x').pathname);
  const [root, rest] = url.startsWith('/data/') ? [data, url.slice(6)] : [web, url.slice(1) || 'index.html'];
  const file = path.resolve(root, rest);
  if (!file.startsWith(path.resolve(root) + path.sep)) {
    response.writeHead(403).end();
    return;
  }
  try {
    if (!(await stat(file)).isFile()) throw new Error('not a file');
    response.writeHead(200, { 'Content-Type': types[path.extname(file)] ?? 'application/octet-stream' });
    createReadStream(file).pipe(response);
  } catch {
    response.writeHead(404).end();
  }
});
server.listen(port, '127.0.0.1', () => {
  console.log(`serving http://localhost:${server.address().port}/ (web/ and ${data} at /data/)`);
});
