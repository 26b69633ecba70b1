// The replay timeline (igms-viewer --log): play, pause, seek and speed. The
// igms process owns the playhead; the page shows it and asks for changes.
const $ = (id) => document.getElementById(id);

export class Timeline {
  constructor(send) {
    this.send = send;
    this.dragging = false;
    $('play').addEventListener('click', () => this.send({ type: 'replay', action: this.playing ? 'pause' : 'play' }));
    const seek = $('seek');
    seek.addEventListener('input', () => { this.dragging = true; });
    seek.addEventListener('change', () => {
      this.dragging = false;
      this.send({ type: 'replay', action: 'seek', t: parseFloat(seek.value) });
    });
    $('speed').addEventListener('change', () =>
      this.send({ type: 'replay', action: 'speed', speed: parseFloat($('speed').value) }));
  }

  update(timeline) {
    $('timeline').hidden = false;
    this.playing = timeline.playing;
    $('play').textContent = timeline.playing ? 'pause' : 'play';
    const seek = $('seek');
    seek.max = String(timeline.end);
    if (!this.dragging) seek.value = String(timeline.t);
    $('timeline-time').textContent = timeline.t.toFixed(3) + ' / ' + timeline.end.toFixed(3) + ' s';
  }
}
