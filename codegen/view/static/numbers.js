// codegen view, numbers for reading: a number in a text the page shows (a run's reading, say) to two decimals (0.01 mm,
// 0.01 deg), never "-0.00"; the data keeps every digit (codegenView.data).
window.codegenNumbers = (function () {
  "use strict";

  function fixed(value, decimals) {
    const text = value.toFixed(decimals);
    return /^-0\.?0*$/.test(text) ? text.slice(1) : text;
  }

  function readable(text) {
    return text.replace(/-?\d+\.\d{3,}(?:e[-+]?\d+)?/g, (m) => fixed(Number(m), 2));
  }

  return { fixed: fixed, readable: readable };
})();
