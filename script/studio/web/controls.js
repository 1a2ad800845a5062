// Parameters as controls (a customizer): one control per parameter, typed from its default —
// a number (a slider beside the box when the recipe gives a range, with its step), a checkbox,
// a choice, or text. The page's address holds the values (`?teeth=16`, beside the token), so a
// view can be shared and reloaded; a change sends them all to the server, which runs the
// recipe again for this page.

// `specs`: [{name, kind, default, min, max, step, choices, doc}] as the recipe declared them
// (may be empty); `values`: {name: text} in force.
export function renderParams(form, specs, values, onChange) {
  const list = specs.length ? specs : Object.keys(values).map((name) => ({ name, default: guess(values[name]) }));
  form.replaceChildren();
  for (const spec of list) {
    const current = values[spec.name] ?? String(spec.value ?? spec.default);
    const label = document.createElement('label');
    label.title = spec.doc ?? '';
    const input = control(spec, current);
    input.name = spec.name;
    input.addEventListener('change', () => onChange(readForm(form)));
    if (input.type === 'checkbox') {
      label.append(input, ` ${spec.name}`);
    } else if (isRanged(spec)) {
      // The slider moves the box as it is dragged; letting go (or typing) runs the recipe.
      const slider = document.createElement('input');
      slider.type = 'range';
      slider.dataset.param = spec.name;
      slider.min = spec.min; slider.max = spec.max; slider.step = input.step; slider.value = current;
      slider.addEventListener('input', () => { input.value = slider.value; });
      slider.addEventListener('change', () => { input.value = slider.value; onChange(readForm(form)); });
      input.addEventListener('input', () => { slider.value = input.value; });
      const row = document.createElement('span');
      row.className = 'ranged';
      row.append(slider, input);
      label.append(`${spec.name} `, row);
    } else {
      label.append(`${spec.name} `, input);
    }
    form.append(label);
  }
  form.closest('section').hidden = list.length === 0;
}

function isRanged(spec) {
  return typeof spec.default === 'number' && spec.min != null && spec.max != null && !spec.choices?.length;
}

function guess(text) {
  if (text === 'true' || text === 'false') return text === 'true';
  return text !== '' && !Number.isNaN(Number(text)) ? Number(text) : text;
}

function control(spec, current) {
  if (Array.isArray(spec.choices) && spec.choices.length) {
    const select = document.createElement('select');
    for (const c of spec.choices) select.append(new Option(String(c), String(c), false, String(c) === current));
    return select;
  }
  const input = document.createElement('input');
  if (typeof spec.default === 'boolean') {
    input.type = 'checkbox';
    input.checked = current === 'true';
  } else if (typeof spec.default === 'number') {
    input.type = 'number';
    if (spec.min != null) input.min = spec.min;
    if (spec.max != null) input.max = spec.max;
    input.step = spec.step ?? (Number.isInteger(spec.default) ? 1 : 'any');
    input.value = current;
  } else {
    input.type = 'text';
    input.value = current;
  }
  return input;
}

// Every named control's value as text, by name.
export function readForm(form) {
  const values = {};
  for (const el of form.elements) {
    if (!el.name) continue;
    values[el.name] = el.type === 'checkbox' ? String(el.checked) : el.value;
  }
  return values;
}

// The parameters in the page's address (all but the token).
export function paramsFromAddress() {
  const values = Object.fromEntries(new URLSearchParams(location.search));
  delete values.token;
  return values;
}

// Puts `values` in the page's address, after the token, without reloading.
export function paramsToAddress(values, token) {
  const query = new URLSearchParams(token ? { token, ...values } : values).toString();
  history.replaceState(null, '', query ? `?${query}` : location.pathname);
}
