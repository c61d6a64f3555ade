#!/usr/bin/env node
// Validates glTF files (.gltf or .glb) with the Khronos glTF-Validator (the `gltf-validator`
// npm package) and prints, per file, one JSON line: the file, the validator's version, the
// numbers of errors, warnings, infos and hints, and the errors' and warnings' messages (code,
// JSON pointer, message).
//
//   node tools/gltf_validate.mjs FILE...
//
// Exit status: 0 when no file has an error, 1 when one has, 2 when a file cannot be read or
// the validator cannot be loaded. External resources of a .gltf (buffers, images) are read
// from beside it. The validator: $FASTBRDF_GLTF_VALIDATOR when set (the package's folder,
// e.g. target/gltf-validator/node_modules/gltf-validator, which tools/test.sh installs; an
// error when it is not there); otherwise target/gltf-validator/ of this repository, then
// wherever Node finds `gltf-validator` (NODE_PATH, a global install).
import { readFile } from "node:fs/promises";
import { existsSync } from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));

function loadValidator() {
    const require = createRequire(import.meta.url);
    const given = process.env.FASTBRDF_GLTF_VALIDATOR;
    if (given) {
        // Named on purpose: that one or an error, never another.
        const dir = path.resolve(given);
        if (!existsSync(path.join(dir, "package.json"))) {
            throw new Error(`FASTBRDF_GLTF_VALIDATOR=${given}: no package.json there (the gltf-validator package's folder)`);
        }
        return require(dir);
    }
    const local = path.join(here, "..", "target", "gltf-validator", "node_modules", "gltf-validator");
    if (existsSync(path.join(local, "package.json"))) {
        return require(local);
    }
    try {
        return require("gltf-validator");
    } catch {
        throw new Error(
            `no gltf-validator (looked in ${local} and Node's module path); install it with ` +
                "`npm install --prefix target/gltf-validator gltf-validator@2.0.0-dev.3.10`",
        );
    }
}

async function validate(validator, file) {
    const bytes = await readFile(file);
    const report = await validator.validateBytes(new Uint8Array(bytes), {
        uri: path.basename(file),
        maxIssues: 0,
        externalResourceFunction: (uri) =>
            readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then(
                (b) => new Uint8Array(b),
            ),
    });
    const issues = report.issues;
    // Severity: 0 error, 1 warning, 2 info, 3 hint.
    const messages = issues.messages
        .filter((m) => m.severity <= 1)
        .map((m) => ({
            severity: m.severity === 0 ? "error" : "warning",
            code: m.code,
            pointer: m.pointer ?? null,
            message: m.message,
        }));
    return {
        file,
        validator: report.validatorVersion,
        errors: issues.numErrors,
        warnings: issues.numWarnings,
        infos: issues.numInfos,
        hints: issues.numHints,
        messages,
    };
}

const files = process.argv.slice(2);
if (files.length === 0 || files.includes("--help") || files.includes("-h")) {
    console.error("usage: node tools/gltf_validate.mjs FILE.glb|FILE.gltf...");
    process.exit(files.length === 0 ? 2 : 0);
}
let validator;
try {
    validator = loadValidator();
} catch (e) {
    console.error(`gltf_validate: ${e.message}`);
    process.exit(2);
}
let status = 0;
for (const file of files) {
    try {
        const r = await validate(validator, file);
        console.log(JSON.stringify(r));
        if (r.errors > 0) status = Math.max(status, 1);
    } catch (e) {
        console.error(`gltf_validate: ${file}: ${e.message ?? e}`);
        status = 2;
    }
}
process.exit(status);
