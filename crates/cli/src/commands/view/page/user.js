// user.js: (placeholder, filled by its owner)
