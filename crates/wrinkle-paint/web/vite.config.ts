// The page is embedded in the `wrinkle` binary with include_bytes!, so the build writes fixed names
// (dist/index.html, dist/assets/app.js, dist/assets/app.css: no content hashes, no other chunks) and is
// deterministic: CI rebuilds it and compares it with the committed dist/.
import { defineConfig } from 'vite';

export default defineConfig({
  base: '/',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    // One script and one stylesheet: nothing inlined as data: URLs, no preload polyfill, no source maps.
    assetsInlineLimit: 0,
    cssCodeSplit: false,
    modulePreload: false,
    sourcemap: false,
    reportCompressedSize: false,
    rollupOptions: {
      output: {
        entryFileNames: 'assets/app.js',
        chunkFileNames: 'assets/app.js',
        assetFileNames: 'assets/app[extname]',
        // No code splitting: a dynamic import, should one appear, is bundled into app.js.
        inlineDynamicImports: true,
      },
    },
  },
});
