import { render } from "preact";
import { App } from "./components/App";
import { applyPalette } from "./palette";
import "./styles.css";

// The stylesheet's palette colours, from the one palette the server draws with.
applyPalette(document.documentElement.style);

const root = document.getElementById("app");
if (root) render(<App />, root);
