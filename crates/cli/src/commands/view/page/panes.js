// panes.js: (placeholder, filled by its owner)
