// Validates a .glb with the Khronos glTF validator; prints its report's issue counts and messages
// as JSON and exits 1 where it finds an error. Usage: node validate.mjs FILE.glb
import { readFileSync } from 'node:fs';
import validator from 'gltf-validator';

const file = process.argv[2];
const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), { maxIssues: 50 });
const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
console.log(JSON.stringify({ numErrors, numWarnings, numInfos, numHints, messages }, null, 1));
process.exit(numErrors > 0 ? 1 : 0);
