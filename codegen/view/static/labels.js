// codegen view, the labels on the screen: of labels that overlap there only the first is shown (in the data's order:
// a station's mark before its poses), so that none is drawn over another and each shown one can be read.
window.codegenLabels = (function () {
  "use strict";

  function overlaps(a, b) { // [left, top, right, bottom] in pixels
    return a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
  }

  // rects: each label's rectangle on the screen, or null where it is off the picture (behind the camera)
  function shown(rects) {
    const kept = [];
    return rects.map((r) => {
      if (!r || kept.some((k) => overlaps(k, r))) return false;
      kept.push(r);
      return true;
    });
  }

  // a sprite's rectangle (pixels) as the camera draws it: its centre projected, its height its world height over the
  // height the picture spans at its distance
  function rect(sprite, camera, width, height) {
    const v = sprite.position.clone().project(camera);
    if (v.z > 1 || v.z < -1) return null;
    const along = sprite.position.clone().sub(camera.position).dot(camera.getWorldDirection(sprite.position.clone()));
    if (along <= 0) return null;
    const spans = 2 * along * Math.tan((camera.fov * Math.PI) / 360);
    const h = (sprite.scale.y / spans) * height, w = (sprite.scale.x / spans) * height;
    const x = ((v.x + 1) / 2) * width, y = ((1 - v.y) / 2) * height;
    return [x - w / 2, y - h / 2, x + w / 2, y + h / 2];
  }

  return { overlaps: overlaps, shown: shown, rect: rect };
})();
