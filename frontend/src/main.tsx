import { render } from "preact";
import { App } from "./components/App";
import { startLanguage } from "./i18n";
import { applyPalette } from "./palette";
import "./styles.css";

// The stylesheet's palette colours, from the one palette the server draws with.
applyPalette(document.documentElement.style);

// The phone's language (its catalogue is a chunk of its own) before the first words are shown.
const root = document.getElementById("app");
void startLanguage().finally(() => {
  if (root) render(<App />, root);
});
