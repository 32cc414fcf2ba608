import { render } from "preact";
import { App } from "./components/App";
import { applyPalette } from "./palette";
import { startShell } from "./shell/update";
import "./styles.css";

// The stylesheet's palette colours, from the one palette the server draws with.
applyPalette(document.documentElement.style);

const root = document.getElementById("app");
if (root) render(<App />, root);

// Installable and offline: the app shell's service worker, and moving to a new build.
startShell();
