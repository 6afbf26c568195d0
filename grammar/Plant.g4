// The Plant language. The parse tree never leaves compiler/parse: a builder turns it
// into our own AST (compiler/ast), one function per rule. Component kinds, properties,
// shapes and parameter types are plain identifiers here and are checked against the
// component registry later, so a new component kind needs no grammar change.
grammar Plant;

@parser::members {
    // True when the next token starts right where the previous one ended.
    bool adjacent() {
        return _input->LT(1)->getStartIndex() == _input->LT(-1)->getStopIndex() + 1;
    }
}

module : item* EOF ;

item
    : importDecl
    | objectDecl
    | plantDecl
    ;

importDecl : 'import' dotted (',' dotted)* ';'? ;
dotted     : ID ('.' ID)* ;

objectDecl : 'object' ID paramList? '{' member* '}' ;
plantDecl  : 'plant' ID paramList? '{' member* '}' ;

paramList : '(' (param (',' param)* ','?)? ')' ;
param     : ID ':' ident ('=' def=expr)? ('where' cond=expr)? ;   // a constraint on the value

// `plant run f.plant --set k=4kg/s`: one command-line value for a plant parameter,
// parsed on its own (not part of a module).
cliSet : ID '=' expr EOF ;

member
    : portDecl ';'?
    | letDecl ';'?
    | flowDecl ';'?
    | logicDecl ';'?
    | forDecl
    | ifDecl
    | recordDecl ';'?
    | settingDecl ';'?
    | instanceDecl ';'?
    | componentDecl
    ;

// in to_base: void => net.MoveToBasePos.put
portDecl     : dir=('in' | 'out') ID ':' ID ('=>' path (',' path)*)? ;
letDecl      : 'let' ID '=' expr ;
// flow a.b -> c.d when source once
flowDecl     : 'flow' (ID ':')? path '->' path flowOption* ;
flowOption   : 'when' ID | 'once' ;
// logic go = r1.seen and not b2.occupied
logicDecl    : 'logic' ID '=' logicTerm (op+=('and' | 'or') logicTerm)* ;
logicTerm    : neg='not'? path ;
forDecl      : 'for' ID 'in' expr ('..' expr)? '{' member* '}' ;   // a range, or the items of a list
ifDecl       : 'if' expr '{' thenBody+=member* '}' ('else' '{' elseBody+=member* '}')? ;
recordDecl   : 'record' path ('as' expr)? ;
settingDecl  : ID '=' expr ;
// b1: Belt(length = 2 m) at (0 m, 0 m, 0 m) rotate z by 90 deg
instanceDecl : ID ('[' expr ']')? ':' ID args? placement? ;
// physics blade: kinematic on frame at (...) { ... }
componentDecl: kindName=ID compName=ID (':' modeName=ID)? ('on' path)? placement? '{' compItem* '}' ;

compItem
    : property ';'?
    | shapeDecl ';'?
    | animationDecl
    | variantDecl ';'?
    | placeDecl ';'?
    | transitionDecl ';'?
    | routeDecl ';'?
    | entryDecl ';'?
    | componentDecl
    ;

property       : ident '=' expr ;
shapeDecl      : 'shape' ID args placement? ;
animationDecl  : 'animation' ID '{' animItem* '}' ;
animItem
    : property ';'?
    | rotation ';'?
    | 'move' expr ';'?
    | 'key' expr placement ';'?
    ;
variantDecl    : 'variant' ID '=' expr ;
placeDecl      : 'place' placeInit (',' placeInit)* ;
placeInit      : ID ('=' expr)? ;
transitionDecl : 'transition' ID ':' arcList? '->' arcList? ;
arcList        : arc ('+' arc)* ;
arc            : (NUMBER '*'?)? ID ;
routeDecl      : (expr | '*') '=>' ID ;   // a string, or a list of strings, or '*'
// coil 3 => s1.to_working(pulse = 1): an entry of a plugin kind's table; the kind's
// descriptor names the words it takes (docs/architecture.md)
entryDecl      : ID expr '=>' path args? ;

placement : 'at' expr rotation* | rotation+ ;
rotation  : 'rotate' axis 'by' expr ;
axis      : ID | '(' expr ',' expr ',' expr ')' ;

args : '(' (arg (',' arg)* ','?)? ')' ;
arg  : (ID '=')? expr ;

// (sensor.object as Bottle).code.value  — a slot of an object known at run time
path
    : '(' path 'as' ID ')' ('.' pathSeg)+   # castPath
    | pathSeg ('.' pathSeg)*                # plainPath
    ;
pathSeg : ident ('[' expr ']')? ;
// `object` is a keyword but also the name of a slot and a property.
ident   : ID | 'object' | 'in' | 'out' ;

expr
    : primary                                               # primaryExpr
    | op='-' expr                                           # unaryExpr
    | expr op=('*' | '/' | '%') expr                        # binaryExpr
    | expr op=('+' | '-') expr                              # binaryExpr
    | expr op=('<' | '<=' | '>' | '>=' | '==' | '!=') expr  # binaryExpr
    | op='not' expr                                         # unaryExpr
    | expr op='and' expr                                    # binaryExpr
    | expr op='or' expr                                     # binaryExpr
    ;

primary
    : NUMBER unit?                              # numberLit
    | STRING                                    # stringLit
    | value=('true' | 'false')                  # boolLit
    | '(' expr ')'                              # parenExpr
    | '(' expr ',' expr (',' expr)* ','? ')'    # tupleExpr
    | '[' (expr (',' expr)* ','?)? ']'          # listExpr
    | ID args                                   # callExpr
    | ID ('[' expr ']')? ('.' ID)*              # nameExpr
    ;

// 50 cm/s, 9.81 m/s^2, 16 N*s/m: a unit directly follows its number.
// Compound units are written without spaces (`cm/s`), so `10 cm * width` multiplies.
unit     : unitAtom ({adjacent()}? unitOp=('*' | '/') {adjacent()}? unitAtom)* ;
unitAtom : ID ({adjacent()}? '^' {adjacent()}? '-'? NUMBER)? ;

NUMBER  : [0-9]+ ('.' [0-9]+)? ([eE] [+-]? [0-9]+)? ;
STRING  : '"' (~["\\\r\n] | '\\' ~[\r\n])* '"' ;   // a backslash escapes a character, never a line break
ID      : [a-zA-Z_] [a-zA-Z_0-9]* ;

// Comments are kept on the hidden channel: the parser never sees them, `plant fmt` does.
DOC_COMMENT  : '///' ~[\r\n]* -> channel(HIDDEN) ;
LINE_COMMENT : '//' ~[\r\n]* -> channel(HIDDEN) ;
BLOCK_COMMENT: '/*' .*? '*/' -> channel(HIDDEN) ;
WS           : [ \t\r\n]+ -> skip ;
// Anything else is one bad token, so the parser reports it with a position.
BAD_CHAR     : . ;
