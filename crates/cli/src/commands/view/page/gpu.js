// gpu.js: (placeholder, filled by its owner)
