import { render } from "preact";
import { App } from "./components/App";
import { startLanguage } from "./i18n";
import { applyPalette } from "./palette";
import { startShell } from "./shell/update";
import "./styles.css";

// The stylesheet's palette colours, from the one palette the server draws with.
applyPalette(document.documentElement.style);

// The phone's language (its catalogue is a chunk of its own) before the first words are shown.
const root = document.getElementById("app");
void startLanguage().finally(() => {
  if (root) render(<App />, root);
});

// Installable and offline: the app shell's service worker, and moving to a new build.
startShell();
