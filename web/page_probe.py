"""How a browser reads the viewer's panel: the JavaScript the end-to-end tests and the
benchmarks evaluate in the page, kept next to the panel whose markup it depends on."""

# The value of the text input next to the control labelled `label` (for a slider: its number
# box), or null when no such label is on the page.
READ_BY_LABEL = """label => {
  const l = [...document.querySelectorAll('label')].find(e => e.textContent.trim() === label);
  if (!l) return null;
  let node = l.parentElement;
  while (node && !node.querySelector('input:not([type=hidden])')) node = node.parentElement;
  return node ? node.querySelector('input:not([type=hidden])').value : null;
}"""

# Mark the text input next to the control labelled `label` with data-probe-box="tag", so that
# a locator can type into it (`[data-probe-box=tag]`).
TAG_BY_LABEL = """([label, tag]) => {
  const l = [...document.querySelectorAll('label')].find(e => e.textContent.trim() === label);
  let node = l.parentElement;
  while (node && !node.querySelector('input:not([type=hidden])')) node = node.parentElement;
  node.querySelector('input:not([type=hidden])').setAttribute('data-probe-box', tag);
}"""
