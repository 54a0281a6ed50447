// "Your asset" (served by `fresnel-lut view --three-js DIR`, fresnel_lut/view.py): a glTF the user drops, in three.js
// 0.187.0 as an application runs it, once as stock three.js and once through the fresnel-basis-three package (its
// GLTFLoader plugin), toggled. Lit by three.js's RoomEnvironment. window.fresnelAsset is the page's interface for
// scripts (the tests load a file and read the state).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { BASIS_HASH, FresnelBasisGLTFPlugin } from 'fresnel-basis-three';

const $ = ( id ) => document.getElementById( id );
const canvas = $( 'canvas' );
const renderer = new THREE.WebGLRenderer( { canvas, antialias: true } );
renderer.setPixelRatio( 1 );
renderer.toneMapping = THREE.NeutralToneMapping;
const scene = new THREE.Scene();
scene.background = new THREE.Color( 0.18, 0.18, 0.18 );
scene.environment = new THREE.PMREMGenerator( renderer ).fromScene( new RoomEnvironment(), 0.02 ).texture;
const camera = new THREE.PerspectiveCamera( 30, canvas.width / canvas.height, 0.01, 1000 );
camera.position.set( 0, 0, 4 );
const controls = new OrbitControls( camera, canvas );
const loaded = { stock: null, basis: null };
const state = { name: null, metals: 0, materials: 0, mode: 'basis', frames: 0 };

function showError( message ) {

	const line = String( message ).split( '\n' )[ 0 ];
	$( 'error' ).textContent = line.length > 300 ? line.slice( 0, 300 ) + '…' : line;
	$( 'error' ).hidden = false;

}

async function parse( data, plugin ) {

	const loader = new GLTFLoader();
	if ( plugin ) loader.register( ( parser ) => new FresnelBasisGLTFPlugin( parser ) );
	return ( await loader.parseAsync( data, '' ) ).scene;

}

function frame( object ) {

	const box = new THREE.Box3().setFromObject( object );
	const size = box.getSize( new THREE.Vector3() ).length() || 1;
	const centre = box.getCenter( new THREE.Vector3() );
	controls.target.copy( centre );
	camera.near = size / 100;
	camera.far = size * 100;
	camera.position.copy( centre ).add( new THREE.Vector3( 0, size * 0.2, size * 1.4 ) );
	camera.updateProjectionMatrix();
	controls.update();

}

function show() {

	for ( const [ mode, object ] of Object.entries( loaded ) ) if ( object ) object.visible = mode === state.mode;
	renderer.render( scene, camera );
	state.frames += 1;

}

async function load( name, data ) {

	$( 'error' ).hidden = true;
	$( 'status' ).textContent = `loading ${ name }…`;
	try {

		const [ stock, basis ] = await Promise.all( [ parse( data, false ), parse( data, true ) ] );
		for ( const object of Object.values( loaded ) ) if ( object ) scene.remove( object );
		Object.assign( loaded, { stock, basis } );
		scene.add( stock, basis );
		const materials = new Set();
		basis.traverse( ( o ) => { if ( o.material ) [].concat( o.material ).forEach( ( m ) => materials.add( m ) ); } );
		state.name = name;
		state.materials = materials.size;
		state.metals = [ ...materials ].filter( ( m ) => m.defines && m.defines.FRESNEL_THREE_MODEL !== undefined ).length;
		frame( basis );
		show();
		$( 'status' ).textContent = `${ name }: ${ state.metals } of ${ state.materials } materials with metal get the basis (basis ${ BASIS_HASH.slice( 0, 8 ) })`;

	} catch ( error ) {

		showError( `${ name } could not be loaded: ${ error.message || error }` );
		$( 'status' ).textContent = 'Choose another file.';

	}

}

async function loadFile( file ) {

	await load( file.name, file.name.toLowerCase().endsWith( '.gltf' ) ? await file.text() : await file.arrayBuffer() );

}

$( 'file' ).addEventListener( 'change', () => { if ( $( 'file' ).files.length ) loadFile( $( 'file' ).files[ 0 ] ); } );
canvas.addEventListener( 'dragover', ( event ) => event.preventDefault() );
canvas.addEventListener( 'drop', ( event ) => {

	event.preventDefault();
	if ( event.dataTransfer.files.length ) loadFile( event.dataTransfer.files[ 0 ] );

} );
$( 'mode' ).addEventListener( 'change', () => { state.mode = $( 'mode' ).value; show(); } );
controls.addEventListener( 'change', show );
$( 'status' ).textContent = 'Drop a glTF on the picture, or choose one.';
show();

window.fresnelAsset = {
	state,
	load,
	setMode( mode ) { $( 'mode' ).value = mode; state.mode = mode; show(); },
	pixels() {

		const gl = renderer.getContext();
		show();
		const out = new Uint8Array( canvas.width * canvas.height * 4 );
		gl.readPixels( 0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, out );
		return Array.from( out );

	},
};
