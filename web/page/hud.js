// The heads-up display: the session's figures from the newest frame, the
// device force bar, and the banners when the server, the client or the
// connection is lost.
const MODES = ['free', 'push', 'pull'];

const $ = (id) => document.getElementById(id);

function fixed(x, digits) { return (typeof x === 'number' && isFinite(x)) ? x.toFixed(digits) : '–'; }

export class Hud {
  constructor() {
    this.deviceLimit = 1;
  }

  role(role) {
    $('role').textContent = role === 'device' ? '· your mouse is the device' : '· viewer';
    $('device-controls').hidden = role !== 'device';
    $('help').textContent = role === 'device'
      ? 'drag a link: push (wheel: deeper / back) · shift-drag: pull (+alt: turn it) · right-drag: orbit · ' +
        'space pause/resume · s step · r reset · w save · v view · c contacts · ' +
        'gamepad: sticks move the tip, A push, B grab'
      : 'drag: orbit · right-drag: pan · wheel: zoom · v: reset view · c: contacts';
  }

  hello(hello) {
    $('scene-name').textContent = (hello.scene || '') + '  ' + (hello.scene_path || '');
    const problems = [];
    if (hello.error) problems.push('scene: ' + hello.error);
    const banner = $('banner-scene');
    banner.textContent = problems.join(' · ');
    banner.hidden = problems.length === 0;
  }

  missingMeshes(list) {
    if (!list.length) return;
    const banner = $('banner-scene');
    banner.textContent = 'meshes not found: ' + list.slice(0, 3).join(', ') + (list.length > 3 ? ' …' : '');
    banner.hidden = false;
  }

  connection(open) { $('banner-connection').hidden = open; }

  notice(text) { $('notice').textContent = text; }

  gamepad(id) { $('gamepad').textContent = id || 'none'; }

  frame(f) {
    $('sim-time').textContent = f.t !== undefined ? fixed(f.t, 3) + ' s' : '–';
    $('mode').textContent = f.mode !== undefined ? (MODES[f.mode] || String(f.mode)) : '–';
    const s = f.server;
    if (s) {
      $('server-state').textContent = s.state + (s.message ? ' · ' + s.message : '');
      $('server-rate').textContent = fixed(s.rate, 0) + ' Hz';
      $('server-step').textContent = fixed(s.step_p50, 0) + ' / ' + fixed(s.step_p99, 0) + ' µs';
      $('server-overruns').textContent = String(s.overruns);
      // Solves cut short at the sweep limit, and answers that kept a slip they could not turn.
      const k = s.contact;
      $('contact-solve').textContent = k && k.solves > 0
        ? k.solves + ' · ' + k.unconverged + ' unconverged · ' + k.slips_unturned + ' slips unturned' : 'none';
      $('pause').textContent = s.state === 'paused' ? 'resume' : 'pause';
    }
    const c = f.client;
    if (c) {
      $('client-rate').textContent = fixed(c.rate, 0) + ' Hz · ' + c.device;
      $('client-misses').textContent = String(c.misses);
      $('client-rtt').textContent = fixed(c.rtt_p50, 0) + ' / ' + fixed(c.rtt_p99, 0) + ' µs';
      $('client-fallback').textContent = c.fallback + ' (' + c.fallbacks + ')';
      $('client-scale').textContent = fixed(c.force_scale, 2);
    }
    const force = f.force ? Math.hypot(...f.force) : 0;
    $('contact-force').textContent = fixed(force, 2) + ' N';
    $('distance').textContent = f.min_distance >= 1e8 ? 'no obstacles'
      : (f.in_collision ? 'IN COLLISION' : fixed(1000 * f.min_distance, 1) + ' mm');
    // The device's rendered force: from the web device, else the client's.
    const rendered = f.device ? f.device.force : (c ? c.rendered_force : null);
    const limit = f.device ? f.device.limit : 10;
    const magnitude = rendered ? Math.hypot(...rendered) : 0;
    $('device-force').textContent = fixed(magnitude, 2) + ' N';
    $('force-fill').style.width = Math.min(100, 100 * magnitude / (limit || 1)).toFixed(1) + '%';
    $('contacts').textContent = f.contacts ? String(f.contacts.total) : '–';
    $('banner-server').hidden = !f.server_lost;
    $('banner-client').hidden = !f.client_lost;
  }
}
