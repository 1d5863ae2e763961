// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The 3-D view: three.js with OrbitControls, +Y up like every glTF viewer (the server's .glb
// and JSON views are already in that frame). Meshes come as .glb (GLTFLoader), skeletons as
// JSON nodes/edges drawn as LineSegments, point sets as JSON points drawn as Points. Rendering
// is on demand (after a camera move, a load or a toggle), which keeps software WebGL cheap.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

export const kBackground = 0xf5f5f2;
const kMeshColour = 0xc8b48e;

export function createView(container) {
  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setClearColor(kBackground, 1);
  container.prepend(renderer.domElement);

  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(30, 1, 0.01, 1000);
  camera.up.set(0, 1, 0);
  camera.position.set(4, 3, 6);
  scene.add(camera);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8d8a80, 1.6));
  const headlight = new THREE.DirectionalLight(0xffffff, 1.6);
  headlight.position.set(0.5, 1, 0.3);
  camera.add(headlight); // a light from over the viewer's shoulder, whichever side they look at
  headlight.target.position.set(0, 0, -1);
  camera.add(headlight.target);

  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.set(0, 0, 0);
  controls.update();

  const root = new THREE.Group();
  scene.add(root);
  const helpers = new THREE.Group();
  scene.add(helpers);

  const settings = { flat: false, wireframe: false, meshMode: 'shown' };
  const entries = new Map(); // object id → {object, kind, visible}
  const cameraListeners = [];
  let generation = 0;
  let pending = false;

  function render() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      renderer.render(scene, camera);
    });
  }

  function resize() {
    const w = Math.max(1, container.clientWidth);
    const h = Math.max(1, container.clientHeight);
    renderer.setSize(w, h, true);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
    cameraListeners.forEach((f) => f('resize'));
  }
  new ResizeObserver(resize).observe(container);

  controls.addEventListener('change', () => {
    render();
    cameraListeners.forEach((f) => f('change'));
  });

  function meshMaterial(hasColours) {
    const faint = settings.meshMode === 'faint';
    return new THREE.MeshStandardMaterial({
      color: hasColours ? 0xffffff : kMeshColour,
      vertexColors: hasColours,
      roughness: 0.75,
      metalness: 0.0,
      flatShading: settings.flat,
      wireframe: settings.wireframe,
      transparent: faint,
      opacity: faint ? 0.25 : 1,
      side: THREE.DoubleSide,
    });
  }

  function restyle() {
    for (const e of entries.values()) {
      if (e.kind !== 'mesh') continue;
      e.object.traverse((o) => {
        if (!o.isMesh) return;
        o.material.dispose();
        o.material = meshMaterial(!!o.geometry.getAttribute('color'));
      });
      e.object.visible = e.visible && settings.meshMode !== 'hidden';
    }
    render();
  }

  async function buildObject(info) {
    if (info.kind === 'mesh') {
      const response = await fetch(info.view);
      if (!response.ok) throw new Error(`${info.view}: ${response.status}`);
      const gltf = await new GLTFLoader().parseAsync(await response.arrayBuffer(), '');
      gltf.scene.traverse((o) => {
        if (o.isMesh) o.material = meshMaterial(!!o.geometry.getAttribute('color'));
      });
      return gltf.scene;
    }
    if (info.kind === 'skeleton') {
      const data = await (await fetch(info.view)).json();
      const positions = new Float32Array(data.nodes.flat());
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      geometry.setIndex(data.edges.flat());
      return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0x7a3b12 }));
    }
    if (info.kind === 'points') {
      const data = await (await fetch(info.view)).json();
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(data.points.flat()), 3));
      return new THREE.Points(geometry, new THREE.PointsMaterial({ color: 0x2f6f3e, size: 3, sizeAttenuation: false }));
    }
    return null; // drawings are SVG pictures shown beside the view
  }

  // Replaces the shown objects by those of a run. Objects of an older call that finish loading
  // later are dropped (the latest run wins). `frame`: fit the camera to the new objects.
  async function setObjects(objects, { frame = true } = {}) {
    const mine = ++generation;
    const built = await Promise.all(
      objects.map((info) => buildObject(info).then((object) => ({ info, object }))),
    );
    if (mine !== generation) return false;
    for (const e of entries.values()) {
      root.remove(e.object);
      e.object.traverse((o) => {
        o.geometry?.dispose();
        o.material?.dispose?.();
      });
    }
    // Visibility carries over by name and kind (ids are per run): a re-run keeps what was hidden.
    const previous = new Map([...entries.values()].map((e) => [`${e.kind}:${e.name}`, e.visible]));
    entries.clear();
    for (const { info, object } of built) {
      if (!object) continue;
      const key = `${info.kind}:${info.name}`;
      const visible = previous.has(key) ? previous.get(key) : true;
      object.name = info.name;
      entries.set(info.id, { object, kind: info.kind, name: info.name, info, visible });
      root.add(object);
    }
    restyle();
    if (frame) frameAll();
    render();
    return true;
  }

  // Shows a mesh of a run that is still going (an entry of its status's `early`, made before
  // its bark UVs and files): it takes the place of the shown mesh of the same script line and
  // shape, keeping its visibility and the camera. Dropped when a run's objects were set while it
  // loaded; the run's own objects replace it when the run ends.
  async function showEarly(info) {
    const mine = generation;
    const object = await buildObject(info);
    if (mine !== generation || !object) return false;
    const old = [...entries.entries()].find(
      ([, e]) => e.kind === 'mesh' && e.info.line === info.line && e.info.shape === info.shape,
    );
    const first = entries.size === 0; // nothing shown yet: look at it once it is there
    const name = old ? old[1].name : info.shape;
    const visible = old ? old[1].visible : true;
    if (old) {
      root.remove(old[1].object);
      old[1].object.traverse((o) => {
        o.geometry?.dispose();
        o.material?.dispose?.();
      });
      entries.delete(old[0]);
    }
    object.name = name;
    entries.set(info.id, { object, kind: 'mesh', name, info, visible });
    root.add(object);
    restyle();
    if (first) frameAll();
    return true;
  }

  const isVisible = (id) => entries.get(id)?.visible ?? true;

  function setVisible(id, visible) {
    const e = entries.get(id);
    if (!e) return;
    e.visible = visible;
    e.object.visible = visible && (e.kind !== 'mesh' || settings.meshMode !== 'hidden');
    render();
  }

  function visibleBox() {
    const box = new THREE.Box3();
    for (const e of entries.values()) if (e.visible) box.expandByObject(e.object, true);
    return box;
  }

  // Looks at the bounding sphere of the visible objects from the current direction, from just
  // far enough for the sphere to fit both the height and the width of the view.
  function frameAll() {
    const box = visibleBox();
    if (box.isEmpty()) return;
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    const radius = Math.max(sphere.radius, 1e-6);
    const vertical = THREE.MathUtils.degToRad(camera.fov);
    const horizontal = 2 * Math.atan(Math.tan(vertical / 2) * camera.aspect);
    const distance = (1.1 * radius) / Math.sin(Math.min(vertical, horizontal) / 2);
    const direction = camera.position.clone().sub(controls.target).normalize();
    if (!Number.isFinite(direction.x) || direction.lengthSq() === 0) direction.set(0, 0, 1);
    controls.target.copy(sphere.center);
    camera.position.copy(sphere.center).addScaledVector(direction, distance);
    camera.near = distance / 100;
    camera.far = distance * 100;
    camera.updateProjectionMatrix();
    controls.update();
    render();
  }

  // What /api/lines needs: the camera in the page's frame and the canvas size in CSS pixels.
  function cameraState() {
    return {
      eye: camera.position.toArray(),
      target: controls.target.toArray(),
      up: camera.up.toArray(),
      fov: camera.fov,
      width: container.clientWidth,
      height: container.clientHeight,
    };
  }

  // The camera's ray through a client pixel.
  function rayAt(clientX, clientY) {
    const rect = renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(
      ((clientX - rect.left) / rect.width) * 2 - 1,
      -((clientY - rect.top) / rect.height) * 2 + 1,
    );
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(ndc, camera);
    return raycaster;
  }

  // The point where the ray through a client pixel meets the plane of unit normal `normal` at
  // signed distance `offset` from the origin, or null when the ray misses it.
  function pick(clientX, clientY, normal, offset = 0) {
    return rayAt(clientX, clientY).ray.intersectPlane(new THREE.Plane(normal, -offset), new THREE.Vector3());
  }

  // The nearest visible mesh surface under a client pixel: {id, info, point} (the run's object
  // and the page-frame point hit), or null.
  function pickObject(clientX, clientY) {
    if (settings.meshMode === 'hidden') return null;
    const meshes = [...entries.entries()].filter(([, e]) => e.kind === 'mesh' && e.visible);
    const hits = rayAt(clientX, clientY).intersectObjects(meshes.map(([, e]) => e.object), true);
    if (hits.length === 0) return null;
    for (let o = hits[0].object; o; o = o.parent) {
      const found = meshes.find(([, e]) => e.object === o);
      if (found) return { id: found[0], info: found[1].info, point: hits[0].point.clone() };
    }
    return null;
  }

  // Where the ray through a client pixel meets the plane through `through` that faces the
  // camera (dragging moves things in it), or null.
  function pointOnViewPlane(clientX, clientY, through) {
    const normal = camera.getWorldDirection(new THREE.Vector3());
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(normal, through);
    return rayAt(clientX, clientY).ray.intersectPlane(plane, new THREE.Vector3());
  }

  // Shows object `id` displaced by the page vector `offset` (a drag in progress; the next run's
  // objects replace it).
  function setOffset(id, offset) {
    const e = entries.get(id);
    if (!e) return;
    e.object.position.copy(offset);
    render();
  }

  // The radius of object `id`'s bounding sphere (0 when unknown).
  function objectSize(id) {
    const e = entries.get(id);
    if (!e) return 0;
    const box = new THREE.Box3().expandByObject(e.object, true);
    return box.isEmpty() ? 0 : box.getBoundingSphere(new THREE.Sphere()).radius;
  }

  // Turns the camera to face a plane through the target ('xy': from the front, +Z; 'xz' and
  // 'skin': from above, +Y), at the same distance, so that clicks land where the user means them.
  function facePlane(planeName) {
    const distance = camera.position.distanceTo(controls.target);
    const direction = planeName === 'xy' ? new THREE.Vector3(0, 0, 1) : new THREE.Vector3(0, 1, 1e-4).normalize();
    controls.target.z = planeName === 'xy' ? 0 : controls.target.z;
    controls.target.y = planeName !== 'xy' ? 0 : controls.target.y;
    camera.position.copy(controls.target).addScaledVector(direction, distance);
    controls.update();
    render();
  }

  // The sketch's helpers: a grid on the plane (at `height` for skin sections), the sections
  // already drawn (closed, fainter) and the polyline so far.
  function showSketch(planeName, points, { height = 0, sections = [] } = {}) {
    helpers.clear();
    if (!planeName) return render();
    const box = visibleBox();
    const size = box.isEmpty() ? 4 : Math.max(2, 2.5 * box.getBoundingSphere(new THREE.Sphere()).radius);
    const grid = new THREE.GridHelper(2 * Math.ceil(size), 2 * Math.ceil(size) * 2, 0x6d7f99, 0xb8c2d0);
    if (planeName === 'xy') grid.rotation.x = Math.PI / 2;
    if (planeName === 'skin') grid.position.y = height;
    helpers.add(grid);
    for (const section of sections) {
      const loop = new THREE.LineLoop(
        new THREE.BufferGeometry().setFromPoints(section),
        new THREE.LineBasicMaterial({ color: 0x9a6b86, depthTest: false }),
      );
      loop.renderOrder = 1;
      helpers.add(loop);
    }
    if (points.length > 0) {
      const geometry = new THREE.BufferGeometry().setFromPoints(points);
      // Drawn over the models (a profile through a solid would hide inside it).
      const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: 0xd0367a, depthTest: false }));
      const dots = new THREE.Points(geometry, new THREE.PointsMaterial({ color: 0xd0367a, size: 7, sizeAttenuation: false, depthTest: false }));
      line.renderOrder = dots.renderOrder = 1;
      helpers.add(line, dots);
    }
    render();
  }

  return {
    renderer,
    camera,
    controls,
    canvas: renderer.domElement,
    setObjects,
    showEarly,
    setVisible,
    isVisible,
    frameAll,
    cameraState,
    pick,
    pickObject,
    pointOnViewPlane,
    setOffset,
    objectSize,
    showSketch,
    facePlane,
    render,
    onCameraChange: (f) => cameraListeners.push(f),
    setFlat(v) { settings.flat = v; restyle(); },
    setWireframe(v) { settings.wireframe = v; restyle(); },
    setMeshMode(v) { settings.meshMode = v; restyle(); },
    // The triangles of the shown meshes (for tests).
    triangles() {
      let n = 0;
      for (const e of entries.values()) {
        if (e.kind !== 'mesh') continue;
        e.object.traverse((o) => {
          if (o.isMesh) n += (o.geometry.index ? o.geometry.index.count : o.geometry.getAttribute('position').count) / 3;
        });
      }
      return n;
    },
    // The visible objects' bounding box (for tests and the status line).
    bounds() {
      const b = visibleBox();
      return b.isEmpty() ? null : { min: b.min.toArray(), max: b.max.toArray() };
    },
  };
}
