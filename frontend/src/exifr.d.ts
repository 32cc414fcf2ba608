// exifr's "lite" build (JPEG and HEIC, TIFF/EXIF): its types are the package's own.
declare module "exifr/dist/lite.esm.mjs" {
  import exifr from "exifr";
  export default exifr;
}
