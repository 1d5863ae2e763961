// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `npm run build` writes dist/ with relative asset paths: the binary serves dist/index.html at
// /?token=... and the assets under /assets/, and the page talks to the API with relative URLs.
import { defineConfig } from 'vite';

export default defineConfig({
  base: './',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    // One bundle for the page and one for three.js; no inlined data: URLs, no source maps.
    assetsInlineLimit: 0,
    sourcemap: false,
    chunkSizeWarningLimit: 1500,
  },
});
