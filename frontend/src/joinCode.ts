/**
 * Join codes as people read and type them: CODE_DIGITS digits (eight), the search's number
 * then its secret, shown in groups of four ("4829 1375"), typed with or without spaces.
 */

import { CODE_DIGITS } from "./limits";

const GROUP = 4;

/** The code in what someone typed (spaces, dashes and dots are ignored), or null. */
export function codeFrom(typed: string): string | null {
  const digits = typed.replace(/[\s.-]/g, "");
  return new RegExp(`^\\d{${CODE_DIGITS}}$`).test(digits) ? digits : null;
}

/** The code in groups of four, as the starter's phone shows it. */
export function codeGroups(code: string): string[] {
  const groups: string[] = [];
  for (let start = 0; start < code.length; start += GROUP) groups.push(code.slice(start, start + GROUP));
  return groups;
}
