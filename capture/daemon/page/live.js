// The capture daemon's live page (docs/live-page.md). Plain JavaScript, no libraries: the daemon serves
// it from its own binary and nothing is fetched from elsewhere. Every text from the daemon goes through
// textContent, never innerHTML.
'use strict';

const $ = (selector) => document.querySelector(selector);

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (key === 'class') node.className = value;
    else if (key.startsWith('data-')) node.setAttribute(key, value);
    else node[key] = value;
  }
  for (const child of children) node.append(child);
  return node;
}

function fmtCount(n) { return n === undefined || n === null ? '–' : String(n); }

function fmtDuration(s) {
  if (s === null || s === undefined) return '–';
  if (s < 120) return `${s.toFixed(0)} s`;
  if (s < 7200) return `${(s / 60).toFixed(0)} min`;
  return `${(s / 3600).toFixed(1)} h`;
}

function fmtBytes(b) { return b >= 1e9 ? `${(b / 1e9).toFixed(1)} GB` : `${(b / 1e6).toFixed(0)} MB`; }

// A table body with one row per key, rows kept (not rebuilt) so the page does not flicker.
function upsertRow(tbody, key, attr, cells) {
  let row = tbody.querySelector(`tr[${attr}="${CSS.escape(key)}"]`);
  if (!row) {
    row = el('tr', {[attr]: key});
    for (const c of cells) row.append(el('td', {class: c.class || ''}));
    tbody.append(row);
  }
  cells.forEach((c, i) => {
    row.children[i].textContent = c.text;
    row.children[i].className = (c.class || '') + (c.bad ? ' bad' : '');
    if (c.name) row.children[i].dataset.name = c.name;
  });
  return row;
}

function showState(status) {
  const state = $('#state');
  state.textContent = status.state;
  state.className = `badge ${status.state}`;
  const s = status.session;
  $('#session').textContent = s && s.name ? s.name : (s && s.session ? s.session : '');
}

function showStreams(status) {
  const tbody = $('#streams tbody');
  const session = status.session && status.session.streams ? status.session.streams : {};
  for (const [name, live] of Object.entries(status.streams || {})) {
    const rec = session[name] || {};
    const age = live.last_age_s;
    upsertRow(tbody, name, 'data-stream', [
      {text: name},
      {text: `${live.rate_hz.toFixed(0)} Hz`, class: 'num rate'},
      {text: fmtCount(rec.received !== undefined ? rec.received : live.received), class: 'num received'},
      {text: fmtCount(rec.written), class: 'num written'},
      {text: fmtCount(rec.dropped), class: 'num dropped', bad: rec.dropped > 0},
      {text: age < 0 ? '–' : `${age.toFixed(1)} s ago`, class: 'num age', bad: age > 1},
    ]);
  }
  const q = status.queues;
  // One frame queue per camera, so a rig with two cameras shows which one falls behind.
  const fill = (name, x) => `${name} ${x.depth}/${x.capacity} (peak ${x.high_water})`;
  const frames = q && q.cameras ? Object.entries(q.cameras).map(([camera, x]) => fill(`frames ${camera}`, x))
                                : (q ? [fill('frames', q.frames)] : []);
  $('#queues').textContent = q ? `queues: ${frames.join(', ')}, ${fill('records', q.records)}` : 'queues: not recording';
  const d = status.disk || {};
  $('#disk').textContent = d.free_bytes === undefined ? `disk: ${d.error || '?'}` :
      `disk: ${fmtBytes(d.free_bytes)} free of ${fmtBytes(d.total_bytes)}` +
      (d.seconds_to_full ? `, full in ${fmtDuration(d.seconds_to_full)} at ${fmtBytes(d.write_bytes_per_s)}/s` : '');
  $('#disk').classList.toggle('bad', !!d.seconds_to_full && d.seconds_to_full < 600);
}

function showBodies(status) {
  const tbody = $('#bodies tbody');
  for (const [tracker, live] of Object.entries(status.streams || {})) {
    for (const [body, b] of Object.entries(live.bodies || {})) {
      const text = b.visible ? 'visible' : (b.status === 'valid' ? 'stale' : b.status.replace(/_/g, ' '));
      upsertRow(tbody, `${tracker}/${body}`, 'data-body', [
        {text: tracker}, {text: body}, {text, class: 'status', bad: !b.visible, name: b.status},
        {text: b.markers === undefined ? '–' : String(b.markers), class: 'num markers'},
      ]);
    }
  }
}

let lastEventSeq = 0;
function showEvents(events) {
  const list = $('#events');
  // A restarted daemon numbers its events from 1 again: start the list afresh.
  if (events.length && events[events.length - 1].seq < lastEventSeq) {
    list.replaceChildren();
    lastEventSeq = 0;
  }
  for (const e of events) {
    if (e.seq <= lastEventSeq) continue;
    lastEventSeq = e.seq;
    const time = new Date(e.wall_ms).toLocaleTimeString();
    list.prepend(el('li', {'data-kind': e.kind, 'data-seq': e.seq},
        `${time} `, el('span', {class: 'kind'}, e.kind), e.stream ? ` ${e.stream}` : '', `: ${e.detail}`));
  }
  while (list.children.length > 200) list.lastChild.remove();
}

// A camera's thumbnail and labels are swapped in together once both have loaded, so the labels always
// lie over the frame they were drawn for.
function showThumbnail(t) {
  let figure = document.querySelector(`figure[data-camera="${CSS.escape(t.camera)}"]`);
  if (!figure) {
    figure = el('figure', {'data-camera': t.camera},
        el('div', {class: 'thumb'}, el('img', {class: 'frame', alt: `${t.camera}`}),
           el('img', {class: 'labels', alt: ''})),
        el('figcaption'));
    $('#cameras').append(figure);
  }
  if (figure.dataset.pending === String(t.seq) || figure.dataset.seq === String(t.seq)) return;
  figure.dataset.pending = t.seq;
  const q = `camera=${encodeURIComponent(t.camera)}&seq=${t.seq}`;
  const frame = new Image();
  const labels = new Image();
  const loads = [new Promise((ok, fail) => { frame.onload = ok; frame.onerror = fail; })];
  frame.src = `/live/thumbnail.jpg?${q}`;
  if (t.labels) {
    loads.push(new Promise((ok, fail) => { labels.onload = ok; labels.onerror = fail; }));
    labels.src = `/live/labels.png?${q}`;
  }
  Promise.all(loads).then(() => {
    if (Number(figure.dataset.seq || 0) > t.seq) return;
    figure.querySelector('img.frame').src = frame.src;
    const shown = figure.querySelector('img.labels');
    shown.src = t.labels ? labels.src : 'data:,';
    shown.hidden = !t.labels;
    figure.dataset.seq = t.seq;
    figure.dataset.frame = t.frame;
    figure.dataset.legend = JSON.stringify(t.legend);
    showCaption(figure.querySelector('figcaption'), t);
  }, () => { delete figure.dataset.pending; });
}

function showCaption(caption, t) {
  caption.replaceChildren(el('b', {}, t.camera), ` frame ${t.frame} `);
  for (const i of t.legend) {
    const chip = el('span', {class: `chip${i.drawn ? '' : ' off'}`, title: i.reason || i.body},
        el('i'), i.object);
    chip.querySelector('i').style.background = i.color;
    caption.append(chip);
  }
  if (t.label_error) caption.append(el('div', {class: 'bad'}, `labels: ${t.label_error}`));
}

function show(snapshot) {
  const status = snapshot.status;
  showState(status);
  showStreams(status);
  showBodies(status);
  showEvents(snapshot.events || []);
  for (const t of snapshot.thumbnails || []) showThumbnail(t);
  document.body.dataset.updates = Number(document.body.dataset.updates || 0) + 1;
}

// Server-Sent Events; when the daemon has no stream slot left (503) or the stream cannot be opened,
// poll the snapshot instead.
function connect() {
  const source = new EventSource('/live/events');
  source.onopen = () => { $('#link').textContent = 'connected'; };
  source.onmessage = (message) => show(JSON.parse(message.data));
  source.onerror = () => {
    $('#link').textContent = 'reconnecting';
    if (source.readyState === EventSource.CLOSED) poll();
  };
}

function poll() {
  $('#link').textContent = 'polling';
  fetch('/live/snapshot', {cache: 'no-store'}).then((r) => r.json()).then((s) => { if (s.status) show(s); })
      .catch(() => {}).finally(() => setTimeout(poll, 1000));
}

async function control(path, body) {
  const message = $('#control-message');
  message.textContent = '';
  try {
    const reply = await fetch(path, {method: 'POST', headers: {'Content-Type': 'application/json'},
                                     body: JSON.stringify(body)});
    const answer = await reply.json();
    message.textContent = reply.ok ? (answer.error ? `failed: ${answer.error}` : `${path.slice(1)}: ok`) : answer.error;
    message.classList.toggle('bad', !reply.ok || !!answer.error);
  } catch (e) {
    message.textContent = `${path}: ${e}`;
    message.classList.add('bad');
  }
}

$('#start-form').addEventListener('submit', (e) => {
  e.preventDefault();
  control('/start', {name: $('#session-name').value});
});
$('#stop').addEventListener('click', () => control('/stop', {}));
// The token of /?token=T is now a cookie: keep it out of the address bar and the history.
if (location.search.includes('token=')) history.replaceState(null, '', '/');
connect();
