/** The join link as a QR code, made on the phone (no service on the internet). */

import qrcode from "qrcode-generator";

export interface QrCode {
  /** Modules per side, without the quiet zone. */
  size: number;
  /** An SVG path of the dark modules, one unit per module. */
  path: string;
}

export function makeQr(text: string): QrCode {
  const code = qrcode(0, "M");
  code.addData(text);
  code.make();
  const size = code.getModuleCount();
  const parts: string[] = [];
  for (let row = 0; row < size; row++) {
    for (let column = 0; column < size; column++) {
      if (code.isDark(row, column)) parts.push(`M${column} ${row}h1v1h-1z`);
    }
  }
  return { size, path: parts.join("") };
}
