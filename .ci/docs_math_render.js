// Opens every rendered doc page that holds mathematics in headless Chromium, lets katex-header.html
// typeset it (KaTeX answered from the local npm copy in place of the CDN), and writes for each page
// the TeX each formula received (the `annotation` element of its MathML), the KaTeX errors and the
// formulas left untypeset. Usage: node docs_math_render.js DOC_DIR CRATE NODE_MODULES OUT_DIR SHOT_PAGE
"use strict";
const fs = require("fs");
const http = require("http");
const path = require("path");

const [docDir, crate, nodeModules, outDir, shotPage] = process.argv.slice(2);
const { chromium } = require(path.join(nodeModules, "playwright-core"));
const katexDist = path.join(nodeModules, "katex", "dist");
const katexVersion = require(path.join(nodeModules, "katex", "package.json")).version;
const cdn = `https://cdn.jsdelivr.net/npm/katex@${katexVersion}/dist/`;

const types = { ".html": "text/html", ".js": "text/javascript", ".css": "text/css", ".svg": "image/svg+xml",
    ".woff2": "font/woff2", ".woff": "font/woff", ".ttf": "font/ttf", ".json": "application/json" };
const mime = (p) => types[path.extname(p)] || "application/octet-stream";

function pages(dir) {
    const found = [];
    for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
        const p = path.join(dir, e.name);
        if (e.isDirectory()) found.push(...pages(p));
        else if (e.name.endsWith(".html")) {
            const s = fs.readFileSync(p, "utf8");
            // A page without a math fence or a `$…$` code span has nothing for KaTeX to typeset.
            if (s.includes('class="language-math"') || /<code>\$[^<]*\$<\/code>/.test(s)) found.push(p);
        }
    }
    return found;
}

async function main() {
    const root = path.resolve(docDir);
    const server = http.createServer((req, res) => {
        const p = path.join(root, decodeURIComponent(new URL(req.url, "http://x").pathname));
        if (!p.startsWith(root) || !fs.existsSync(p) || fs.statSync(p).isDirectory()) {
            res.writeHead(404);
            res.end();
            return;
        }
        res.writeHead(200, { "Content-Type": mime(p) });
        res.end(fs.readFileSync(p));
    });
    await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
    const base = `http://127.0.0.1:${server.address().port}/`;

    const userDataDir = fs.mkdtempSync(path.join(require("os").tmpdir(), "docs-math-chromium-"));
    const context = await chromium.launchPersistentContext(userDataDir, {
        executablePath: "/usr/bin/chromium",
        headless: true,
        args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync"],
        viewport: { width: 1280, height: 1600 },
    });
    let cdnRequests = 0;
    const blocked = [];
    await context.route("**/*", (route) => {
        const url = route.request().url();
        if (url.startsWith(cdn)) {
            cdnRequests++;
            const p = path.join(katexDist, url.slice(cdn.length).split(/[?#]/)[0]);
            return fs.existsSync(p)
                ? route.fulfill({ status: 200, contentType: mime(p), body: fs.readFileSync(p) })
                : route.fulfill({ status: 404, body: "" });
        }
        if (url.startsWith(base)) return route.continue();
        blocked.push(url);
        return route.abort();
    });

    const list = pages(path.join(root, crate));
    const results = [];
    const worker = async () => {
        const page = await context.newPage();
        const errors = [];
        page.on("pageerror", (e) => errors.push(String(e)));
        for (;;) {
            const file = list.shift();
            if (!file) break;
            const rel = path.relative(root, file);
            await page.goto(base + rel, { waitUntil: "load" });
            await page.waitForFunction(() => document.readyState === "complete");
            const r = await page.evaluate(() => ({
                formulas: [...document.querySelectorAll(".katex")]
                    .filter((k) => !k.parentElement.closest(".katex"))
                    .map((k) => {
                        const a = k.querySelector('annotation[encoding="application/x-tex"]');
                        return { display: !!k.closest(".katex-display"), tex: a ? a.textContent : null };
                    }),
                // `.katex-error` marks TeX KaTeX could not parse; a command it does not know is typeset
                // as red text instead, so each formula's TeX is parsed again with errors thrown.
                errors: [...document.querySelectorAll(".katex-error")].map((e) => e.getAttribute("title") || e.textContent)
                    .concat([...document.querySelectorAll('.katex annotation[encoding="application/x-tex"]')].flatMap((a) => {
                        try {
                            katex.renderToString(a.textContent, { throwOnError: true, strict: "error" });
                            return [];
                        } catch (e) {
                            return [String(e.message || e)];
                        }
                    })),
                untypeset: document.querySelectorAll("pre.language-math").length,
                katexLoaded: typeof katex !== "undefined",
            }));
            results.push({ page: rel, ...r, scriptErrors: errors.splice(0) });
            if (rel === shotPage) await page.screenshot({ path: path.join(outDir, path.basename(path.dirname(rel)) + ".png"), fullPage: false });
        }
        await page.close();
    };
    await Promise.all([worker(), worker()]);
    await context.close();
    server.close();
    fs.rmSync(userDataDir, { recursive: true, force: true });
    fs.writeFileSync(path.join(outDir, "rendered.json"),
        JSON.stringify({ katexVersion, cdnRequests, blocked, pages: results }, null, 1));
}

main().catch((e) => {
    console.error(e);
    process.exit(1);
});
