// test data: writes the Draco fixtures in tests/draco/ with Google's encoder. Run: node tools/make-draco-assets.mjs ../shared/khronos tests/draco
// Writes Draco-compressed variants of the shared Khronos Box and Duck with Google's Draco
// encoder (the draco3dgltf package) through glTF-Transform, for tests/gltf/draco.rs.
// Usage (from the repository root):
//   npm install --prefix .tools @gltf-transform/core@4.5.1 @gltf-transform/extensions@4.5.1 \
//       @gltf-transform/functions@4.5.1 draco3dgltf@1.5.7
//   node tools/make-draco-assets.mjs ../shared/khronos tests/draco
// The encoder's defaults: POSITION 14 bits, NORMAL 10, TEXCOORD 12, edgebreaker.
import { createRequire } from 'module';
import path from 'path';
import fs from 'fs';
const require = createRequire(path.resolve('.tools/node_modules/x.js'));
const { NodeIO } = require('@gltf-transform/core');
const { KHRDracoMeshCompression, ALL_EXTENSIONS } = require('@gltf-transform/extensions');
const { draco } = require('@gltf-transform/functions');
const draco3d = require('draco3dgltf');

const [src, out] = process.argv.slice(2);
fs.mkdirSync(out, { recursive: true });
const io = new NodeIO()
  .registerExtensions(ALL_EXTENSIONS)
  .registerDependencies({
    'draco3d.encoder': await draco3d.createEncoderModule(),
    'draco3d.decoder': await draco3d.createDecoderModule(),
  });
for (const [name, file] of [['Box', 'Box/glTF-Binary/Box.glb'], ['Duck', 'Duck/glTF-Binary/Duck.glb']]) {
  const doc = await io.read(path.join(src, file));
  await doc.transform(draco({ method: 'edgebreaker' }));
  // Keep the Draco-compressed geometry only: the texture stays in the shared original.
  for (const texture of doc.getRoot().listTextures()) texture.dispose();
  await io.write(path.join(out, `${name}-draco.glb`), doc);
  console.log(`${name}-draco.glb`, fs.statSync(path.join(out, `${name}-draco.glb`)).size, 'bytes');
}
