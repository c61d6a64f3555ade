// kinds.js: (placeholder, filled by its owner)
