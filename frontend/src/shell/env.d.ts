/// <reference types="vite/client" />

interface ImportMetaEnv {
  /** The build's name (vite build with VITE_APP_VERSION set): src/shell/update.ts. */
  readonly VITE_APP_VERSION?: string;
}
