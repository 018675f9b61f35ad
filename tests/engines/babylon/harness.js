// The Babylon.js harness page's module (tests/engines/babylon/harness.html): renders brdfbake's
// preview grid with Babylon.js 8.46.2 itself (the chunks setup_babylon.py laid out under ../babylon/)
// into a FLOAT render target and hands back linear radiance. babylon_render.py serves this folder
// on 127.0.0.1 and calls window.brdfbakeRender(config) through Selenium.
//
// Linear radiance out of the PBR shader: imageProcessingConfiguration.applyByPostProcess = true (no
// post-process attached) and skipFinalColorClamp = true make pbrBlockImageProcessing end at
// finalColor = max(finalColor, 0) (IMAGEPROCESSINGPOSTPROCESS and SKIPFINALCOLORCLAMP defined);
// isEnabled = false would still run applyImageProcessing's toGammaSpace and saturate.
//
// Units: one world unit is one preview pixel. The camera is orthographic, `distance` pixels away
// along the preview's v = -view_direction (Babylon's view vector is eye - position, so a far eye
// makes it the orthographic one to distance/width), with the preview's up vector.

const B = {};  // the Babylon.js classes, by role (chunks.json)

async function loadBabylon() {
  if (B.Engine) return;
  const chunks = await (await fetch("../babylon/chunks.json")).json();
  for (const [role, [file, name]] of Object.entries(chunks.roles)) {
    const m = await import(`../babylon/assets/${file}`);
    if (!(name in m)) throw new Error(`${file} has no export ${name} (${role})`);
    B[role] = m[name];
  }
  B.version = chunks.babylon_version;
  // Each class is the one its role names (the chunks are minified: check what they say they are).
  const classes = {Scene: "Scene", PBRMaterial: "PBRMaterial", CubeTexture: "CubeTexture", Mesh: "Mesh",
                   HDRCubeTexture: "HDRCubeTexture",
                   TargetCamera: "TargetCamera", Vector3: "Vector3", Color3: "Color3", Color4: "Color4",
                   ImageProcessingConfiguration: "ImageProcessingConfiguration", Matrix: "Matrix"};
  for (const [role, cls] of Object.entries(classes)) {
    const got = B[role].prototype.getClassName.call(Object.create(B[role].prototype));
    if (got !== cls) throw new Error(`role ${role}: the export is a ${got}`);
  }
  if (B.Engine.Version !== B.version) throw new Error(`Engine.Version ${B.Engine.Version}, expected ${B.version}`);
  if (typeof B.RenderTargetTexture.prototype.readPixels !== "function") throw new Error("not a RenderTargetTexture");
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function b64(view) {
  const bytes = new Uint8Array(view.buffer, view.byteOffset, view.byteLength);
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  return btoa(s);
}

function dtypeOf(view) {
  if (view instanceof Float32Array) return "float32";
  if (view instanceof Uint16Array) return "float16";
  if (view instanceof Uint8Array) return "uint8";
  return view.constructor.name;
}

async function waitFor(what, ready, timeoutMs) {
  const t0 = performance.now();
  while (!ready()) {
    if (performance.now() - t0 > timeoutMs) throw new Error(`timed out waiting for ${what}`);
    await sleep(10);
  }
}

// A UV sphere of radius 1 (positions = normals), the same as babylon_render.py's glTF spheres
// (gradio's chunks leave out Babylon.js's sphereBuilder, so VertexData.CreateSphere throws).
function sphereVertexData(segments) {
  const rings = segments, sectors = 2 * segments;
  const positions = [], indices = [];
  for (let i = 0; i <= rings; ++i) {
    const t = Math.PI * i / rings;
    for (let j = 0; j <= sectors; ++j) {
      const p = 2 * Math.PI * j / sectors;
      positions.push(Math.sin(t) * Math.sin(p), Math.cos(t), Math.sin(t) * Math.cos(p));
    }
  }
  for (let i = 0; i < rings; ++i) {
    for (let j = 0; j < sectors; ++j) {
      const a = i * (sectors + 1) + j, b = (i + 1) * (sectors + 1) + j;
      // Clockwise seen from outside in a left-handed frame: Babylon.js's front faces.
      if (i > 0) indices.push(a, a + 1, b);
      if (i < rings - 1) indices.push(a + 1, b + 1, b);
    }
  }
  const vd = new B.VertexData();
  vd.positions = positions;
  vd.normals = positions.slice();
  vd.indices = indices;
  return vd;
}

const DEFINES = ["REFLECTION", "REFLECTIONMAP_3D", "REFLECTIONMAP_CUBIC", "REFLECTIONMAP_OPPOSITEZ", "GAMMAREFLECTION",
  "RGBDREFLECTION", "LODBASEDMICROSFURACE", "LODINREFLECTIONALPHA", "LINEARSPECULARREFLECTION", "SPECULARAA",
  "MIX_IBL_RADIANCE_WITH_IRRADIANCE", "LEGACY_SPECULAR_ENERGY_CONSERVATION", "MS_BRDF_ENERGY_CONSERVATION",
  "BRDF_V_HEIGHT_CORRELATED", "USESPHERICALFROMREFLECTIONMAP", "USESPHERICALINVERTEX", "USEIRRADIANCEMAP",
  "IMAGEPROCESSINGPOSTPROCESS", "SKIPFINALCOLORCLAMP", "BASE_DIFFUSE_MODEL", "DIELECTRIC_SPECULAR_MODEL",
  "CONDUCTOR_SPECULAR_MODEL", "ENVIRONMENTBRDF", "ENVIRONMENTBRDF_RGBD", "METALLICWORKFLOW", "RADIANCEOCCLUSION",
  "HORIZONOCCLUSION", "INVERTCUBICMAP", "REALTIME_FILTERING", "SPHERICAL_HARMONICS", "ALPHAFRESNEL", "SPECULARTERM"];

function definesOf(mesh) {
  const effect = mesh.subMeshes && mesh.subMeshes[0] && mesh.subMeshes[0].effect;
  if (!effect) return null;
  const text = effect.defines || "";
  const out = {};
  for (const name of DEFINES) {
    const m = text.match(new RegExp(`#define ${name}(?:[ \\t]+(\\S+))?[ \\t]*(?:\\n|$)`));
    out[name] = m ? (m[1] === undefined ? true : m[1]) : false;
  }
  return out;
}

function applyOptions(material, o) {
  if (o.mixIbl !== null && o.mixIbl !== undefined) material.brdf.mixIblRadianceWithIrradiance = o.mixIbl;
  if (o.legacyEnergy !== null && o.legacyEnergy !== undefined) material.brdf.useLegacySpecularEnergyConservation = o.legacyEnergy;
  if (o.specularAA !== null && o.specularAA !== undefined) material.enableSpecularAntiAliasing = o.specularAA;
  if (o.irradianceInFragment !== null && o.irradianceInFragment !== undefined) material.forceIrradianceInFragment = o.irradianceInFragment;
}

function setDefaults(o) {
  // The PBRBRDFConfiguration class's defaults, for every material made from now on (reached
  // through an instance: the class is not exported on its own).
  // Each render starts from Babylon.js's own defaults (the page renders many times).
  const probe = new B.PBRMaterial("__probe__", null);
  const BRDF = probe.brdf.constructor;
  probe.dispose();
  if (!B.brdfDefaults) {
    B.brdfDefaults = {mix: BRDF.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE,
                      legacy: BRDF.DEFAULT_USE_LEGACY_SPECULAR_ENERGY_CONSERVATION};
  }
  BRDF.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE =
      o.mixIbl !== null && o.mixIbl !== undefined ? o.mixIbl : B.brdfDefaults.mix;
  BRDF.DEFAULT_USE_LEGACY_SPECULAR_ENERGY_CONSERVATION =
      o.legacyEnergy !== null && o.legacyEnergy !== undefined ? o.legacyEnergy : B.brdfDefaults.legacy;
  return {DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE: BRDF.DEFAULT_MIX_IBL_RADIANCE_WITH_IRRADIANCE,
          DEFAULT_USE_LEGACY_SPECULAR_ENERGY_CONSERVATION: BRDF.DEFAULT_USE_LEGACY_SPECULAR_ENERGY_CONSERVATION};
}

function textureInfo(tex) {
  if (!tex) return null;
  const it = tex.getInternalTexture ? tex.getInternalTexture() : tex._texture;
  const m = tex.getReflectionTextureMatrix ? tex.getReflectionTextureMatrix().toArray() : null;
  return {className: tex.getClassName(), gammaSpace: tex.gammaSpace, isRGBD: tex.isRGBD, level: tex.level,
          lodGenerationScale: tex.lodGenerationScale, lodGenerationOffset: tex.lodGenerationOffset,
          size: tex.getSize().width, invertZ: tex.invertZ, coordinatesMode: tex.coordinatesMode,
          internalType: it ? it.type : null, internalFormat: it ? it.format : null, invertY: it ? it.invertY : null,
          generateMipMaps: it ? it.generateMipMaps : null, reflectionMatrix: m ? Array.from(m) : null,
          sphericalPolynomial: !!tex.sphericalPolynomial};
}

// Reads a cube texture back, level by level (texture.readPixels(face, level)), as Babylon holds it
// on the GPU: rows in the order GL stores them (row 0 = t = 0 of the face).
async function readCube(tex, levels) {
  const out = [];
  const size = tex.getSize().width;
  for (const level of levels) {
    const faces = [];
    for (let face = 0; face < 6; ++face) {
      const px = await tex.readPixels(face, level, null, true, false);
      faces.push({dtype: dtypeOf(px), data: b64(px)});
    }
    out.push({level, size: Math.max(1, size >> level), faces});
  }
  return out;
}

window.brdfbakeRender = async function (cfg) {
  const t0 = performance.now();
  await loadBabylon();
  const o = cfg.options || {};
  const W = cfg.width, H = cfg.height;
  const canvas = document.getElementById("canvas");
  canvas.width = W; canvas.height = H;
  const engine = new B.Engine(canvas, false, {preserveDrawingBuffer: true, stencil: false, antialias: false,
                                              doNotHandleContextLost: true, audioEngine: false}, false);
  const gl = engine._gl;
  const dbg = gl.getExtension("WEBGL_debug_renderer_info");
  const info = {babylon: B.Engine.Version, webgl: engine.webGLVersion,
                renderer: dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER),
                userAgent: navigator.userAgent, colorBufferFloat: !!gl.getExtension("EXT_color_buffer_float")};
  const scene = new B.Scene(engine);
  try {
    scene.useRightHandedSystem = !!cfg.rightHanded;
    scene.clearColor = new B.Color4(0, 0, 0, 0);
    scene.ambientColor = new B.Color3(0, 0, 0);
    const ip = scene.imageProcessingConfiguration;
    ip.applyByPostProcess = true;   // no post-process is attached: the shader writes linear radiance
    ip.skipFinalColorClamp = true;  // ... ended by max(color, 0), no clamp at 30
    info.brdfDefaults = setDefaults(o);

    const V3 = (a) => new B.Vector3(a[0], a[1], a[2]);
    const cam = cfg.camera;
    const right = cam.right, up = cam.up, v = cam.view_direction.map((x) => -x);
    // A left-handed scene's world is the environment's (right-handed) frame mirrored in x, as
    // Babylon.js's own loaders bring content in: the glTF loader puts glTF (x, y, z) at (-x, y, z) (its
    // __root__: rotation 180 degrees about Y, scale (1, 1, -1)), HDRCubeTexture shows a panorama's +X at
    // world -X, and brdfbake's .env stores the environment mirrored so (docs/ENGINES.md). The spheres
    // and camera of "env" and "hdr" are placed the same way; a left-handed camera then sees the preview's
    // image unmirrored. A right-handed scene takes the frame as it is.
    const sx = !cfg.rightHanded ? -1 : 1;
    const M = (a) => [sx * a[0], a[1], a[2]];
    info.mirrored = false;

    let meshes = [];
    if (cfg.mode === "env" || cfg.mode === "hdr") {
      // "hdr": Babylon.js's own conversion of an equirect (.hdr) into a cube (HDRCubeTexture, not
      // prefiltered, box-filtered mips): the frame Babylon.js gives a panorama, for the orientation probe.
      const tex = cfg.mode === "env" ? B.CubeTexture.CreateFromPrefilteredData(cfg.envUrl, scene)
                                     : new B.HDRCubeTexture(cfg.hdrUrl, scene, cfg.hdrSize || 256, false, true, false, false);
      await waitFor("the environment cube", () => tex.isReady(), 60000);
      if (o.gammaSpace !== null && o.gammaSpace !== undefined) tex.gammaSpace = o.gammaSpace;
      scene.environmentTexture = tex;
      const segments = cfg.segments || 64;
      const proto = new B.Mesh("sphere", scene);
      sphereVertexData(segments).applyToMesh(proto, false);
      proto.setEnabled(false);
      cfg.spheres.forEach((s, k) => {
        const m = s.material;
        const mat = new B.PBRMaterial(`m${k}_${s.name || ""}`, scene);
        mat.albedoColor = new B.Color3(m.baseColor[0], m.baseColor[1], m.baseColor[2]);
        mat.metallic = m.metallic;
        mat.roughness = m.roughness;
        if (m.ior !== undefined) mat.indexOfRefraction = m.ior;
        if (m.specular !== undefined) mat.metallicF0Factor = m.specular;
        if (m.specular_color !== undefined) mat.metallicReflectanceColor = new B.Color3(...m.specular_color);
        applyOptions(mat, o);
        const mesh = proto.clone(`s${k}`);
        mesh.setEnabled(true);
        const dx = s.centre[0] - W / 2, dy = s.centre[1] - H / 2;
        mesh.position = V3(M([0, 1, 2].map((i) => dx * right[i] - dy * up[i])));
        mesh.scaling = new B.Vector3(s.radius, s.radius, s.radius);
        mesh.material = mat;
        meshes.push(mesh);
      });
    } else {
      // SceneLoader's LoadAssetContainerAsync (gradio's chunks export it; AppendSceneAsync is left
      // out), then addAllToScene: the same glTF loader, extensions and materials as Append.
      const container = await B.LoadAssetContainerAsync(cfg.gltfUrl, scene, {});
      container.addAllToScene();
      await waitFor("the glTF's environment", () => scene.environmentTexture && scene.environmentTexture.isReady(), 60000);
      if (o.gammaSpace !== null && o.gammaSpace !== undefined) scene.environmentTexture.gammaSpace = o.gammaSpace;
      info.loadedMeshes = scene.meshes.map((m) => [m.name, m.getTotalVertices(), m.isEnabled()]);
      meshes = scene.meshes.filter((m) => m.getTotalVertices() > 0);
      for (const m of meshes) if (m.material) applyOptions(m.material, o);
    }
    info.environment = textureInfo(scene.environmentTexture);

    const D = cfg.distance || 1e7;
    const camera = new B.TargetCamera("camera", V3(M(v).map((x) => D * x)), scene);
    camera.upVector = V3(M(up));
    camera.setTarget(new B.Vector3(0, 0, 0));
    camera.mode = 1;  // Camera.ORTHOGRAPHIC_CAMERA
    camera.orthoLeft = -W / 2; camera.orthoRight = W / 2; camera.orthoTop = H / 2; camera.orthoBottom = -H / 2;
    const extent = Math.hypot(W, H);
    camera.minZ = D - extent; camera.maxZ = D + extent;
    scene.activeCamera = camera;

    const rt = new B.RenderTargetTexture("radiance", {width: W, height: H}, scene,
        {generateMipMaps: false, type: 1 /* FLOAT */, format: 5 /* RGBA */, samplingMode: 1, generateDepthBuffer: true,
         generateStencilBuffer: false, samples: 1});
    rt.activeCamera = camera;
    rt.renderList = meshes;
    rt.clearColor = new B.Color4(0, 0, 0, 0);
    rt.refreshRate = 1;
    scene.customRenderTargets.push(rt);
    await scene.whenReadyAsync();
    const t1 = performance.now();
    for (let i = 0; ; ++i) {
      scene.render();
      if (rt.isReadyForRendering() && meshes.every((m) => m.isReady(true))) break;
      if (i > 2000) throw new Error("the render target never became ready");
      await sleep(10);
    }
    scene.render();
    const px = await rt.readPixels(0, 0, null, true, false);
    info.renderSeconds = (performance.now() - t1) / 1000;
    info.defines = {};
    for (const m of meshes) info.defines[m.material ? m.material.name : m.name] = definesOf(m);
    info.materials = meshes.map((m) => m.material && {name: m.material.name, albedo: m.material.albedoColor && m.material.albedoColor.asArray(),
      metallic: m.material.metallic, roughness: m.material.roughness,
      specularAA: m.material.enableSpecularAntiAliasing, mixIbl: m.material.brdf.mixIblRadianceWithIrradiance,
      legacyEnergy: m.material.brdf.useLegacySpecularEnergyConservation, position: m.getAbsolutePosition().asArray()});
    const result = {width: W, height: H, dtype: dtypeOf(px), pixels: b64(px), info};
    if (cfg.readCubeLevels) result.cube = await readCube(scene.environmentTexture, cfg.readCubeLevels);
    info.totalSeconds = (performance.now() - t0) / 1000;
    return result;
  } finally {
    scene.dispose();
    engine.dispose();
  }
};

window.brdfbakeReady = true;
