/**
 * The names of controls that show no words of their own (a hidden file input behind a
 * picture of a camera, say), and the app's title for screen readers. Words only: every
 * English word of the app's accessibility lives in this folder (describe.ts says why).
 */

/** The file input that opens the camera (the "Take photo" button and the camera icon). */
export const TAKE_PHOTO = "Take a photo of the other side";
/** The file input that opens the gallery ("Choose from gallery"). */
export const PICK_PHOTO = "Choose a photo of the other side from the gallery";
/** What the two photo inputs are, as a part of the page (a named region). */
export const PHOTO_INPUTS = "Your photo";
/** The tap screen's level-one heading, for screen readers only (the photo is its title). */
export const TAP_SCREEN_TITLE = "Buddy Search: your photo";
/** The list of what is drawn on the photo. */
export const MARKS_TITLE = "Marks on your photo";
/** The share screen's level-one heading, for screen readers only (the code is its title). */
export const SHARE_SCREEN_TITLE = "Buddy Search: share the code with your friend";
