// Screenshots of the views as shown: one 2-D view, the 3-D view, or the whole layout, composed
// from the canvases on screen (images, crosshair, outlines, letters, scale and colour bars) at
// the display's pixel ratio or a chosen scale. The 3-D view at full quality is the server's
// (`screenshot` message, toolbar.js).

const MAX_SIDE = 8192;  // a canvas larger than this may fail to allocate

// The region of the page a screenshot of `what` covers.
function regionOf(what) {
  if (what === 'layout') return document.getElementById('view-area');
  if (what === '3d') return document.getElementById('cell-3d');
  return document.querySelector(`.slice-cell[data-axis="${what}"]`);
}

// A canvas of `what` ('layout', '3d', 'axial', 'coronal', 'sagittal') at `scale` device pixels
// per CSS pixel (default the display's devicePixelRatio); null when it is not shown.
export function captureView(what, scale) {
  const region = regionOf(what);
  if (!region || !region.clientWidth || !region.clientHeight) return null;
  const box = region.getBoundingClientRect();
  const k = Math.min(scale > 0 ? scale : window.devicePixelRatio || 1,
                     MAX_SIDE / Math.max(box.width, box.height));
  const out = document.createElement('canvas');
  out.width = Math.round(box.width * k);
  out.height = Math.round(box.height * k);
  const g = out.getContext('2d');
  g.imageSmoothingQuality = 'high';
  g.fillStyle = getComputedStyle(region).backgroundColor || '#000';
  g.fillRect(0, 0, out.width, out.height);
  const place = (r) => [(r.left - box.left) * k, (r.top - box.top) * k, r.width * k, r.height * k];
  const cells = region.classList.contains('cell') ? [region] : region.querySelectorAll('.cell');
  for (const cell of cells) {
    if (!cell.clientWidth) continue;  // not in this layout
    g.fillStyle = getComputedStyle(cell).backgroundColor || '#000';
    g.fillRect(...place(cell.getBoundingClientRect()));
    for (const c of cell.querySelectorAll('canvas')) {
      const r = c.getBoundingClientRect();
      if (c.width && c.height && r.width && r.height) g.drawImage(c, ...place(r));
    }
  }
  return out;
}

// Downloads a screenshot of `what` as PNG.
export function downloadView(what, scale) {
  const canvas = captureView(what, scale);
  if (!canvas) return;
  canvas.toBlob((blob) => {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `intermix-${what}.png`;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  }, 'image/png');
}
