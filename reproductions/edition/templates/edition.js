(function(){
  var box=document.getElementById('filters');box.hidden=false;
  var sel={verdict:document.getElementById('f-verdict'),reason:document.getElementById('f-reason'),
           section:document.getElementById('f-section')};
  var rows=document.querySelectorAll('article.row');var shown=document.getElementById('f-shown');
  function apply(){var n=0;
    rows.forEach(function(r){var ok=true;
      for(var k in sel){var v=sel[k].value;if(v&&r.dataset[k]!==v){ok=false;}}
      r.hidden=!ok;if(ok){n++;}});
    document.querySelectorAll('section.experiment').forEach(function(s){
      var any=!!s.querySelector('article.row:not([hidden])');s.querySelector('.none').hidden=any;
      s.querySelectorAll('figure, .rows-heading').forEach(function(e){e.hidden=!any;});});
    shown.textContent=n+' of '+rows.length+' rows shown';}
  for(var k in sel){sel[k].addEventListener('change',apply);}
  document.addEventListener('click',function(e){
    var a=e.target.closest('a[href^="#"]');if(!a){return;}
    var t=document.getElementById(decodeURIComponent(a.getAttribute('href').slice(1)));
    if(t&&t.closest('[hidden]')){for(var k in sel){sel[k].value='';}apply();}});
  apply();
})();
