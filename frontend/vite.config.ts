/// <reference types="vitest/config" />
// One config for the dev server, the production build and the unit tests. The npm scripts run
// from the repository root, so every path here is anchored to this file, not to the cwd.
import react from "@vitejs/plugin-react";
import { defineConfig } from "vite";

const here = decodeURIComponent(new URL(".", import.meta.url).pathname);
const backend = "http://127.0.0.1:8000";

export default defineConfig({
  root: here,
  base: "/",
  plugins: [react()],
  build: {
    // The backend serves this folder: /assets/* as files, every other path falls back to
    // index.html so the browser's own routes (/nodes/1/od) survive a reload.
    outDir: `${here}../backend/servodesk/static`,
    emptyOutDir: true,
    assetsDir: "assets",
    sourcemap: false,
  },
  server: {
    proxy: {
      "/api": { target: backend, ws: true },
      // rerun's viewer and its gRPC-web stream, both served through the backend
      "/rerun/": { target: backend },
      "/rerun.sdk_comms.v1alpha1.MessageProxyService": { target: backend },
    },
  },
  test: {
    root: here,
    environment: "jsdom",
    include: ["src/**/*.test.{ts,tsx}"],
    setupFiles: ["src/test/setup.ts"],
    restoreMocks: true,
    testTimeout: 20000, // a 2-core machine running the browser tests beside: see setup.ts
  },
});
