/** The unit tests speak English: the catalogue given at once (no chunk to fetch). */
import en from "./locales/en.json";
import { speak } from "./index";

await speak("en", en);
