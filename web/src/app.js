// Constants several of the page's modules share: the element lookup, the
// server's status and health names, the cars' colours. The page's state
// lives in the modules that own it (main.js lists them); window.groundsim,
// the tests' view of it, is hooks.js.

export const $ = (id) => document.getElementById(id);
export const STATUS = { 1: 'running', 2: 'paused', 3: 'finished', 4: 'diverged', 5: 'stopped' };
export const HEALTH = { 0: 'ok', 1: 'non-finite', 2: 'penetration', 3: 'speed', 4: 'energy' };
// one colour per car, by its index in the session
export const COLORS = [0xc8372d, 0x2f6fd0, 0x3fa34d, 0xe0a030, 0x8e4fc4, 0x2fb0b0, 0xd8d8d8, 0x303438];
