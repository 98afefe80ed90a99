// kincalc view: the 3D view, drawn on a canvas with the painter's algorithm.
//
// A camera orbits a centre point: azimuth about the world z axis (up), elevation above
// the xy plane. Orthographic: a point projects along the viewing direction; perspective:
// through an eye at EYE_DISTANCE radii from the centre. Everything to draw is a list of
// primitives (lines, filled polygons, labels) in world coordinates, sorted far to near.
"use strict";

const Scene = (() => {
  const DEFAULT_VIEW = { azimuth: -60, elevation: 25 }; // degrees, as matplotlib's 3D axes
  const EYE_DISTANCE = 4; // perspective: the eye's distance from the centre, in radii
  const DRAG_SPEED = 0.01; // radians per pixel
  const ZOOM_SPEED = 0.0015; // per wheel delta unit

  function create(canvas, { centre, radius, projection = "orthographic" }) {
    const ctx = canvas.getContext("2d");
    const view = { projection, centre, radius };
    let primitives = [];
    let width = 0, height = 0;

    function reset() {
      view.azimuth = DEFAULT_VIEW.azimuth * Math.PI / 180;
      view.elevation = DEFAULT_VIEW.elevation * Math.PI / 180;
      view.zoom = 1;
    }

    // the camera's unit vectors: right and up on the screen, forward into it
    function basis() {
      const ca = Math.cos(view.azimuth), sa = Math.sin(view.azimuth);
      const ce = Math.cos(view.elevation), se = Math.sin(view.elevation);
      return {
        right: [-sa, ca, 0],
        up: [-se * ca, -se * sa, ce],
        forward: [-ce * ca, -ce * sa, -se],
      };
    }

    // a world point (m) -> [x, y] on the canvas (CSS pixels) and its depth (larger: farther)
    function projector() {
      const b = basis();
      const scale = view.zoom * 0.45 * Math.min(width, height) / view.radius;
      const eye = EYE_DISTANCE * view.radius;
      return (p) => {
        const d = [p[0] - view.centre[0], p[1] - view.centre[1], p[2] - view.centre[2]];
        const x = d[0] * b.right[0] + d[1] * b.right[1] + d[2] * b.right[2];
        const y = d[0] * b.up[0] + d[1] * b.up[1] + d[2] * b.up[2];
        const z = d[0] * b.forward[0] + d[1] * b.forward[1] + d[2] * b.forward[2];
        // perspective: shrink with the distance from the eye (kept in front of it)
        const f = view.projection === "perspective" ? eye / Math.max(eye + z, 0.05 * eye) : 1;
        return [width / 2 + scale * f * x, height / 2 - scale * f * y, z];
      };
    }

    function resize() {
      const dpr = window.devicePixelRatio || 1;
      width = canvas.clientWidth;
      height = canvas.clientHeight;
      canvas.width = Math.round(width * dpr);
      canvas.height = Math.round(height * dpr);
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    }

    function draw(list) {
      if (list) primitives = list;
      if (canvas.clientWidth !== width || canvas.clientHeight !== height) resize();
      const project = projector();
      ctx.clearRect(0, 0, width, height);
      const items = primitives.map((p) => {
        const pts = p.points.map(project);
        const depth = pts.reduce((s, v) => s + v[2], 0) / pts.length + (p.bias || 0) * view.radius;
        return { p, pts, depth };
      });
      items.sort((a, b) => b.depth - a.depth);
      for (const { p, pts } of items) paint(p, pts);
    }

    function paint(p, pts) {
      ctx.save();
      ctx.lineCap = "round";
      ctx.lineJoin = "round";
      ctx.setLineDash(p.dash || []);
      if (p.kind === "label") {
        ctx.fillStyle = p.colour;
        ctx.font = p.font || "12px system-ui, sans-serif";
        const [dx, dy] = p.shift || [4, -4];
        ctx.strokeStyle = "rgba(255, 255, 255, 0.85)"; // a halo: legible over the links
        ctx.lineWidth = 3;
        ctx.strokeText(p.text, pts[0][0] + dx, pts[0][1] + dy);
        ctx.fillText(p.text, pts[0][0] + dx, pts[0][1] + dy);
      } else {
        ctx.beginPath();
        pts.forEach(([x, y], k) => (k ? ctx.lineTo(x, y) : ctx.moveTo(x, y)));
        if (p.kind === "polygon") {
          ctx.closePath();
          ctx.fillStyle = p.fill;
          ctx.fill();
        }
        if (p.colour) {
          ctx.strokeStyle = p.colour;
          ctx.lineWidth = p.width || 1;
          ctx.stroke();
        }
      }
      ctx.restore();
    }

    // drag to rotate, wheel to zoom, double click to reset
    let drag = null;
    canvas.addEventListener("pointerdown", (e) => {
      drag = { x: e.clientX, y: e.clientY };
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener("pointermove", (e) => {
      if (!drag) return;
      view.azimuth -= (e.clientX - drag.x) * DRAG_SPEED;
      const limit = Math.PI / 2 - 1e-3; // never look straight down the up axis
      view.elevation = Math.max(-limit, Math.min(limit,
        view.elevation + (e.clientY - drag.y) * DRAG_SPEED));
      drag = { x: e.clientX, y: e.clientY };
      draw();
    });
    const stop = () => { drag = null; };
    canvas.addEventListener("pointerup", stop);
    canvas.addEventListener("pointercancel", stop);
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      view.zoom = Math.max(0.05, Math.min(50, view.zoom * Math.exp(-e.deltaY * ZOOM_SPEED)));
      draw();
    }, { passive: false });
    canvas.addEventListener("dblclick", () => { reset(); draw(); });

    reset();
    return {
      draw,
      reset() { reset(); draw(); },
      setProjection(kind) { view.projection = kind; draw(); },
      project: (p) => projector()(p),
      view,
    };
  }

  return { create };
})();
