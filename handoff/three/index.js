// fresnel-basis-three: the Fresnel of a basis (Belcour, Bati, Barla 2020) in three.js's MeshStandardMaterial and
// MeshPhysicalMaterial, for image-based light, punctual lights and RectAreaLight, from one half-float texture.
//
// Written by hand once (handoff/three/index.js of fresnel-basis); `fresnel-lut build --three` copies it beside
// data.js, which it generates from the basis: the include as a string, the tables packed in one atlas of half
// floats, and the basis hash that both carry (checked here before anything is drawn).
//
// The material keeps three.js's lobe, light loops, diffuse and clear coat; the patch replaces its Fresnel:
//   - the dielectric part stays three.js's Schlick(specularColor, F90), but preintegrated exactly (the project's
//     Schlick table, 128 x 128, in place of three.js's 16 x 16 DFG table);
//   - the metal part is the basis (Gulbrandsen's edge colour, or (eta, kappa)) or OpenPBR's F82 tint, exactly;
//   - both are mixed by metalness, which is exact: F is linear in each.
// Iridescence's image-based light stays three.js's own.

import { ClampToEdgeWrapping, DataTexture, HalfFloatType, LinearFilter, REVISION, RGBAFormat, ShaderChunk, Vector3, Vector4 } from 'three';
import { ATLAS, BASIS_HASH, INCLUDE, THREE_REVISION } from './data.js';

export { BASIS_HASH, THREE_REVISION };

// The metal's Fresnel model (FRESNEL_THREE_MODEL in the shader).
export const MODELS = Object.freeze( { gulbrandsen: 0, nk: 1, 'f82-tint': 2, coefficients: 3 } );

export class FresnelBasisError extends Error {

	constructor( message ) {

		super( message );
		this.name = 'FresnelBasisError';

	}

}

// The code every patched material's fragment shader gains: the include, the atlas, the material's parameters, and
// the glue that fills three.js's quantities from them once per pixel (fresnelThreeSetUp, from lights_fragment_begin).
const GLUE = /* glsl */`
uniform sampler2D fresnelBasisAtlas;
uniform vec3 fresnelBasisEdge;
uniform vec3 fresnelBasisTint;
uniform vec3 fresnelBasisEta;
uniform vec3 fresnelBasisKappa;
uniform vec4 fresnelBasisCoefficients[ 3 ];

// The pixel's Fresnel: the dielectric's Schlick weights (D), the metal's linear weights (M, F82 tint) or basis
// coefficients (C), the metalness that mixes them, and what the lights read (three.js's DFG pair, the F0 of its
// direct-light compensation (Turquin 2019 eq. 16) from the model itself, the split sums).
vec3 fresnelThreeDR, fresnelThreeDG, fresnelThreeDB;
vec3 fresnelThreeMR, fresnelThreeMG, fresnelThreeMB;
vec4 fresnelThreeCR, fresnelThreeCG, fresnelThreeCB;
float fresnelThreeMetalness;
vec2 fresnelThreeDfg;
vec3 fresnelThreeF0;
vec3 fresnelThreeSingleDielectric, fresnelThreeMultiDielectric, fresnelThreeSingleMetal, fresnelThreeMultiMetal;

void fresnelThreeSetUp( vec3 baseColor, vec3 specularColor, float specularF90, float metalness, vec3 tint, float NdotV, float roughness ) {

	// three.js blends F90 by metalness (mix(specularIntensity, 1, metalness)): the dielectric's own F90 back
	float f90 = ( metalness < 1.0 ) ? clamp( ( specularF90 - metalness ) / ( 1.0 - metalness ), 0.0, 1.0 ) : 1.0;
	fresnelThreeDR = fresnelLinearSchlick( specularColor.r, f90 );
	fresnelThreeDG = fresnelLinearSchlick( specularColor.g, f90 );
	fresnelThreeDB = fresnelLinearSchlick( specularColor.b, f90 );
	fresnelThreeMetalness = metalness;
	// each table read once: the split sums and their multiple-scattering terms (Kulla-Conty / Fdez-Aguera: E is the
	// Schlick table's B and the basis table's b0) come from these texels
	vec4 schlick = textureLod( fresnelBasisAtlas, fresnelAtlasSchlick( fresnelBasisLutUV( NdotV, roughness ) ), 0.0 );
	fresnelThreeDfg = schlick.xy;  // three.js's DFG (scale, bias) for what still reads it (direct-light compensation)
	fresnelThreeSingleDielectric = fresnelLinearWeigh( schlick, fresnelThreeDR, fresnelThreeDG, fresnelThreeDB );
	#if FRESNEL_THREE_MULTIPLE_SCATTERING
		fresnelThreeMultiDielectric = fresnelCompensate( fresnelThreeSingleDielectric, schlick.z, fresnelLinearAverage( fresnelThreeDR, fresnelThreeDG, fresnelThreeDB ) ) - fresnelThreeSingleDielectric;
	#else
		fresnelThreeMultiDielectric = vec3( 0.0 );
	#endif

	#if FRESNEL_THREE_MODEL == 2
		fresnelThreeMR = fresnelLinearF82Tint( baseColor.r, tint.r );
		fresnelThreeMG = fresnelLinearF82Tint( baseColor.g, tint.g );
		fresnelThreeMB = fresnelLinearF82Tint( baseColor.b, tint.b );
		fresnelThreeSingleMetal = fresnelLinearWeigh( schlick, fresnelThreeMR, fresnelThreeMG, fresnelThreeMB );
		#if FRESNEL_THREE_MULTIPLE_SCATTERING
			fresnelThreeMultiMetal = fresnelCompensate( fresnelThreeSingleMetal, schlick.z, fresnelLinearAverage( fresnelThreeMR, fresnelThreeMG, fresnelThreeMB ) ) - fresnelThreeSingleMetal;
		#endif
	#else
		#if FRESNEL_THREE_MODEL == 3
			fresnelThreeCR = fresnelBasisCoefficients[ 0 ];
			fresnelThreeCG = fresnelBasisCoefficients[ 1 ];
			fresnelThreeCB = fresnelBasisCoefficients[ 2 ];
		#elif FRESNEL_THREE_MODEL == 1
			fresnelThreeCR = fresnelCoefficientsNK( fresnelBasisEta.r, fresnelBasisKappa.r );
			fresnelThreeCG = fresnelCoefficientsNK( fresnelBasisEta.g, fresnelBasisKappa.g );
			fresnelThreeCB = fresnelCoefficientsNK( fresnelBasisEta.b, fresnelBasisKappa.b );
		#else
			fresnelThreeCR = fresnelCoefficientsGulbrandsen( baseColor.r, fresnelBasisEdge.r );
			fresnelThreeCG = fresnelCoefficientsGulbrandsen( baseColor.g, fresnelBasisEdge.g );
			fresnelThreeCB = fresnelCoefficientsGulbrandsen( baseColor.b, fresnelBasisEdge.b );
		#endif
		vec4 terms = fresnelBasisTerms( fresnelBasisAtlas, fresnelBasisLutUV( NdotV, roughness ) );
		fresnelThreeSingleMetal = vec3( fresnelTermsDot( fresnelThreeCR, terms ), fresnelTermsDot( fresnelThreeCG, terms ), fresnelTermsDot( fresnelThreeCB, terms ) );
		#if FRESNEL_THREE_MULTIPLE_SCATTERING
			fresnelThreeMultiMetal = fresnelCompensate( fresnelThreeSingleMetal, terms.x, fresnelBasisAverage( fresnelThreeCR, fresnelThreeCG, fresnelThreeCB ) ) - fresnelThreeSingleMetal;
		#endif
	#endif
	#if ! FRESNEL_THREE_MULTIPLE_SCATTERING
		fresnelThreeMultiMetal = vec3( 0.0 );
	#endif
	#if FRESNEL_THREE_MODEL == 2
		vec3 metalF0 = vec3( fresnelThreeMR.x, fresnelThreeMG.x, fresnelThreeMB.x );
	#else
		vec3 metalF0 = vec3( fresnelThreeCR.x, fresnelThreeCG.x, fresnelThreeCB.x );
	#endif
	fresnelThreeF0 = mix( vec3( fresnelThreeDR.x, fresnelThreeDG.x, fresnelThreeDB.x ), metalF0, metalness );

}

// F(V.H) for punctual lights: the dielectric's and the metal's, mixed by metalness.
vec3 fresnelThreeDirect( float dotVH ) {

	vec3 dielectric = fresnelLinearDirect( dotVH, fresnelThreeDR, fresnelThreeDG, fresnelThreeDB );
	#if FRESNEL_THREE_MODEL == 2
		vec3 metal = fresnelLinearDirect( dotVH, fresnelThreeMR, fresnelThreeMG, fresnelThreeMB );
	#else
		vec3 metal = fresnelBasisDirect( dotVH, fresnelThreeCR, fresnelThreeCG, fresnelThreeCB );
	#endif
	return mix( dielectric, metal, fresnelThreeMetalness );

}
`;

// Each patch: the chunk, the text that must stand in it exactly once in three.js r187's build (build/three.module.js,
// whose chunks have their blank lines and comments stripped), and what replaces it.
export const PATCHES = Object.freeze( [
	[ 'lights_physical_pars_fragment', 'uniform sampler2D dfgLUT;\n', 'uniform sampler2D dfgLUT;\n' + INCLUDE + GLUE ],
	[
		'lights_physical_pars_fragment',
		'vec3 F = F_Schlick( f0, f90, dotVH );\n\t#ifdef USE_IRIDESCENCE',
		'vec3 F = fresnelThreeDirect( dotVH );\n\t#ifdef USE_IRIDESCENCE',
	],
	[
		'lights_physical_pars_fragment',
		'vec3 fresnel = ( material.specularColorBlended * t2.x + ( material.specularF90 - material.specularColorBlended ) * t2.y );',
		'vec3 fresnel = mix( fresnelThreeSingleDielectric, fresnelThreeSingleMetal, fresnelThreeMetalness );',
	],
	[
		'lights_physical_pars_fragment',
		'computeMultiscattering( material.dfg, material.specularColor, material.specularF90, singleScatteringDielectric, multiScatteringDielectric );\n' +
			'\t\tcomputeMultiscattering( material.dfg, material.diffuseColor, material.specularF90, singleScatteringMetallic, multiScatteringMetallic );',
		'singleScatteringDielectric = fresnelThreeSingleDielectric;\n\t\tmultiScatteringDielectric = fresnelThreeMultiDielectric;\n' +
			'\t\tsingleScatteringMetallic = fresnelThreeSingleMetal;\n\t\tmultiScatteringMetallic = fresnelThreeMultiMetal;',
	],
	[
		'lights_physical_pars_fragment',
		'computeMultiscattering( material.dfg, material.specularColor, material.specularF90, singleScattering, multiScattering );',
		'singleScattering = fresnelThreeSingleDielectric;\n\t\tmultiScattering = fresnelThreeMultiDielectric;',
	],
	[
		'lights_fragment_begin',
		'material.dfg = texture2D( dfgLUT, vec2( material.roughness, dotNVms ) ).rg;',
		'#if defined( IOR )\n\t\tvec3 fresnelThreeTint = fresnelBasisTint * specularColorFactor;\n\t#else\n' +
			'\t\tvec3 fresnelThreeTint = fresnelBasisTint;\n\t#endif\n' +
			'\tfresnelThreeSetUp( material.diffuseColor, material.specularColor, material.specularF90, material.metalness, fresnelThreeTint, dotNVms, material.roughness );\n' +
			'\tmaterial.dfg = fresnelThreeDfg;',
	],
	[
		'lights_fragment_begin',
		'material.multiScatteringCompensation = 1.0 + material.specularColorBlended * ( 1.0 / EssMs - 1.0 );',
		'material.multiScatteringCompensation = 1.0 + fresnelThreeF0 * ( 1.0 / EssMs - 1.0 );',
	],
] );

// three.js's chunks with the patches applied, { chunk name: text }; a FresnelBasisError names the first anchor that
// does not stand exactly once (another three.js release moved it: this package is pinned to THREE_REVISION).
export function patchChunks( chunks = ShaderChunk ) {

	const patched = {};
	for ( const [ name, anchor, replacement ] of PATCHES ) {

		const text = name in patched ? patched[ name ] : chunks[ name ];
		if ( typeof text !== 'string' ) throw new FresnelBasisError( `three.js has no shader chunk ${ name } (this package patches r${ THREE_REVISION })` );
		const count = text.split( anchor ).length - 1;
		if ( count !== 1 ) {

			throw new FresnelBasisError( `three.js r${ REVISION }'s ${ name } holds ${ count } copies of the text this package (made for r${ THREE_REVISION }) replaces: ${ JSON.stringify( anchor.slice( 0, 80 ) ) }` );

		}

		patched[ name ] = text.replace( anchor, () => replacement );

	}

	return patched;

}

function checkData() {

	const hash = INCLUDE.match( /const uint FRESNEL_BASIS_HASH = 0x([0-9a-f]{8})u;/ );
	if ( hash === null || ! BASIS_HASH.startsWith( hash[ 1 ] ) || ATLAS.basisHash !== BASIS_HASH ) {

		throw new FresnelBasisError( `the include (basis ${ hash && hash[ 1 ] }) and the tables (basis ${ ATLAS.basisHash }) are of different bases: rebuild with fresnel-lut build --three` );

	}

}

let atlasTexture = null;

// The atlas (every table the include reads, one RGBA half-float texture; bilinear, clamp, no mipmaps).
export function getFresnelBasisAtlas() {

	if ( atlasTexture === null ) {

		checkData();
		const bytes = Uint8Array.from( atob( ATLAS.data ), ( c ) => c.charCodeAt( 0 ) );  // little-endian half floats
		const halves = new Uint16Array( bytes.buffer );
		if ( halves.length !== ATLAS.width * ATLAS.height * 4 ) {

			throw new FresnelBasisError( `the atlas holds ${ halves.length } half floats, not ${ ATLAS.width } x ${ ATLAS.height } x 4` );

		}

		atlasTexture = new DataTexture( halves, ATLAS.width, ATLAS.height, RGBAFormat, HalfFloatType );
		atlasTexture.name = 'fresnel_basis_atlas';
		atlasTexture.minFilter = LinearFilter;
		atlasTexture.magFilter = LinearFilter;
		atlasTexture.wrapS = ClampToEdgeWrapping;
		atlasTexture.wrapT = ClampToEdgeWrapping;
		atlasTexture.generateMipmaps = false;
		atlasTexture.needsUpdate = true;

	}

	return atlasTexture;

}

function toVector( name, value, fallback ) {

	if ( value === undefined ) return fallback.clone();
	const v = value.isColor ? new Vector3( value.r, value.g, value.b ) : ( value.isVector3 ? value.clone() : Array.isArray( value ) && value.length === 3 ? new Vector3( ...value ) : null );
	if ( v === null || ! [ v.x, v.y, v.z ].every( Number.isFinite ) ) {

		throw new FresnelBasisError( `${ name } must be a Color, a Vector3 or three finite numbers, got ${ value }` );

	}

	return v;

}

function toCoefficients( value ) {

	if ( value === undefined ) return [ 0, 1, 2 ].map( () => new Vector4( 0, 0, 0, 0 ) );
	const rows = Array.isArray( value ) && value.length === 3 ? value.map( ( row ) => Array.from( row ) ) : null;
	if ( rows === null || ! rows.every( ( row ) => row.length === 4 && row.every( Number.isFinite ) ) ) {

		throw new FresnelBasisError( 'coefficients must be three rows (R, G, B) of four finite numbers (c0 .. c3)' );

	}

	return rows.map( ( row ) => new Vector4( ...row ) );

}

// Give `material` (a MeshStandardMaterial or MeshPhysicalMaterial) the basis Fresnel. Options:
//   model: 'gulbrandsen' (default; reflectivity = the material's color and map, edge = options.edge),
//          'nk' (options.eta, options.kappa per colour channel), or 'f82-tint' (F0 = the material's color, tint =
//          options.tint times a physical material's specularColor and specularColorMap: OpenPBR's specular_color),
//          or 'coefficients' (options.coefficients: the basis coefficients, rows R, G, B of c0 .. c3, from the Python
//          API, `fresnel-lut coeffs --json` or luts/materials.json; they must be of this package's basis);
//   edge, tint, eta, kappa: Color, Vector3 or [r, g, b] (linear);
//   multipleScattering: true (default; Fdez-Aguera 2019 with the basis' own E and F_avg) or false.
// Returns the uniforms, whose .value may be changed afterwards (edge, tint, eta, kappa).
export function applyFresnelBasis( material, options = {} ) {

	if ( ! material || ! material.isMeshStandardMaterial ) {

		throw new FresnelBasisError( 'applyFresnelBasis takes a MeshStandardMaterial or MeshPhysicalMaterial' );

	}

	const known = [ 'model', 'edge', 'tint', 'eta', 'kappa', 'coefficients', 'multipleScattering' ];
	const unknown = Object.keys( options ).filter( ( key ) => ! known.includes( key ) );
	if ( unknown.length > 0 ) throw new FresnelBasisError( `unknown options ${ unknown.join( ', ' ) } (known: ${ known.join( ', ' ) })` );
	const model = options.model === undefined ? 'gulbrandsen' : options.model;
	if ( ! ( model in MODELS ) ) throw new FresnelBasisError( `model must be one of ${ Object.keys( MODELS ).join( ', ' ) }, got ${ model }` );
	if ( REVISION !== THREE_REVISION ) {

		console.warn( `fresnel-basis-three was made for three.js r${ THREE_REVISION }; this is r${ REVISION } (the patch checks every anchor)` );

	}

	const chunks = patchChunks();  // refused here, before the material is touched, if three.js moved an anchor
	const uniforms = {
		fresnelBasisAtlas: { value: getFresnelBasisAtlas() },
		fresnelBasisEdge: { value: toVector( 'edge', options.edge, new Vector3( 1, 1, 1 ) ) },
		fresnelBasisTint: { value: toVector( 'tint', options.tint, new Vector3( 1, 1, 1 ) ) },
		fresnelBasisEta: { value: toVector( 'eta', options.eta, new Vector3( 1.5, 1.5, 1.5 ) ) },
		fresnelBasisKappa: { value: toVector( 'kappa', options.kappa, new Vector3( 0, 0, 0 ) ) },
		fresnelBasisCoefficients: { value: toCoefficients( options.coefficients ) },
	};
	const multipleScattering = options.multipleScattering === undefined ? true : Boolean( options.multipleScattering );
	material.defines = Object.assign( {}, material.defines, {
		FRESNEL_THREE_MODEL: MODELS[ model ],
		FRESNEL_THREE_MULTIPLE_SCATTERING: multipleScattering ? 1 : 0,
	} );
	const previous = material.onBeforeCompile;
	material.onBeforeCompile = ( shader, renderer ) => {

		previous.call( material, shader, renderer );
		Object.assign( shader.uniforms, uniforms );
		for ( const [ name, text ] of Object.entries( chunks ) ) {

			shader.fragmentShader = shader.fragmentShader.replace( `#include <${ name }>`, () => text );

		}

	};

	const key = material.customProgramCacheKey.bind( material );
	material.customProgramCacheKey = () => `${ key() }|fresnel-basis:${ BASIS_HASH }:${ model }:${ multipleScattering }`;
	material.needsUpdate = true;
	return uniforms;

}

// A GLTFLoader plugin (loader.register( ( parser ) => new FresnelBasisGLTFPlugin( parser ) )): every material with
// metal in it (metallicFactor > 0, glTF's default 1) gets the basis Fresnel as OpenPBR's F82 tint, with
// KHR_materials_specular's specularColorFactor and specularColorTexture as the tint, per pixel, for metals as
// EXT_materials_specular_openpbr proposes (three.js already reads them into specularColor / specularColorMap, which
// its dielectric part keeps using as KHR_materials_specular says). A material without the extension has tint 1:
// Schlick's curve, integrated exactly.
export class FresnelBasisGLTFPlugin {

	constructor( parser, options = {} ) {

		this.parser = parser;
		this.name = 'fresnel_basis';
		this.options = Object.assign( { model: 'f82-tint', tint: [ 1, 1, 1 ] }, options );

	}

	afterRoot( result ) {

		const materials = new Set();
		for ( const scene of result.scenes ) {

			scene.traverse( ( object ) => {

				if ( object.material ) [].concat( object.material ).forEach( ( m ) => materials.add( m ) );

			} );

		}

		for ( const material of materials ) {

			const association = this.parser.associations.get( material );
			if ( ! material.isMeshStandardMaterial || ! association || association.materials === undefined ) continue;
			const definition = this.parser.json.materials[ association.materials ];
			const metallic = ( definition.pbrMetallicRoughness || {} ).metallicFactor;
			if ( metallic === 0 ) continue;
			applyFresnelBasis( material, this.options );

		}

	}

}
